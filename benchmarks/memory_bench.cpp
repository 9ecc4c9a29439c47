// memory_bench: the peak resident memory of one large search against the memory model of
// docs/memory.md. Not a test: one search per process, so that the process's peak (getrusage's
// ru_maxrss) is that search's; benchmarks/memory_bench.sh runs the cases.
//
// The system: N random atoms (--atoms, default 10^7) at a liquid's density (--density, atoms per
// A^3, default 0.0334, water) in a triclinic cell (angles 80, 95, 110 degrees); a cutoff
// (--cutoff, A), full or half (--half), i, j, S, d stored (--quantities, any of ijSdD with i and
// j), unordered or --grouped or --sorted, on --threads T threads, with --max-pairs P and
// --max-bytes B (0: no limit; by default the library's). Prints the resident memory after the
// positions are made (the caller's O(N)), after build() (the search's O(N)), the peak, the pairs,
// the bytes of the returned arrays, the list's peak by the library's model (list_memory(), what
// max_bytes is checked against) and the bound: after build + 1.2 x the model's peak. A refused
// search prints its message and the peak, which must then be only the O(N) parts.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include <Eigen/LU>
#include <sys/resource.h>

#include <tricell/box.hpp>
#include <tricell/error.hpp>
#include <tricell/neighbor_list.hpp>

#include "policy/list_limits.hpp"

namespace {

// Resident memory now and the process's peak, from /proc/self/status (kB -> bytes).
double status_bytes(const char* field) {
    std::FILE* f = std::fopen("/proc/self/status", "r");
    if (f == nullptr) {
        return 0;
    }
    char line[256];
    double kb = 0;
    const std::size_t length = std::strlen(field);
    while (std::fgets(line, sizeof line, f) != nullptr) {
        if (std::strncmp(line, field, length) == 0) {
            kb = std::atof(line + length + 1);
        }
    }
    std::fclose(f);
    return kb * 1024;
}

double peak_bytes() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return double(usage.ru_maxrss) * 1024;
}

double gib(double bytes) {
    return bytes / double(1u << 30);
}

} // namespace

int main(int argc, char** argv) {
    std::size_t atoms = 10'000'000;
    double density = 0.0334, cutoff = 5;
    tricell::NeighborOptions options;
    std::string quantities = "ijSd";
    for (int a = 1; a < argc; ++a) {
        const std::string arg = argv[a];
        const bool has_value = a + 1 < argc;
        if (arg == "--atoms" && has_value) {
            atoms = std::size_t(std::atof(argv[++a]));
        } else if (arg == "--density" && has_value) {
            density = std::atof(argv[++a]);
        } else if (arg == "--cutoff" && has_value) {
            cutoff = std::atof(argv[++a]);
        } else if (arg == "--threads" && has_value) {
            options.threads = std::atoi(argv[++a]);
        } else if (arg == "--max-pairs" && has_value) {
            options.max_pairs = std::size_t(std::atof(argv[++a]));
        } else if (arg == "--max-bytes" && has_value) {
            options.max_bytes = std::size_t(std::atof(argv[++a]));
        } else if (arg == "--quantities" && has_value) {
            quantities = argv[++a];
        } else if (arg == "--half") {
            options.half = true;
        } else if (arg == "--grouped") {
            options.grouped = true;
        } else if (arg == "--sorted") {
            options.sorted = true;
        } else {
            std::fprintf(stderr, "memory_bench: unknown argument %s\n", arg.c_str());
            return 2;
        }
    }
    options.cutoff = cutoff;
    options.quantities.shifts = quantities.find('S') != std::string::npos;
    options.quantities.distances = quantities.find('d') != std::string::npos;
    options.quantities.vectors = quantities.find('D') != std::string::npos;

    // A cell of volume N / density with angles 80, 95, 110 degrees and edges in ratio 1 : 1.1 :
    // 0.9.
    const tricell::Box unit = tricell::Box::from_parameters(1, 1.1, 0.9, 80, 95, 110);
    const double scale = std::cbrt(double(atoms) / density / std::abs(unit.matrix().determinant()));
    const tricell::Box box =
        tricell::Box::from_parameters(scale, 1.1 * scale, 0.9 * scale, 80, 95, 110);
    std::vector<double> xyz(3 * atoms);
    {
        std::mt19937_64 random(12345);
        std::uniform_real_distribution<double> u(0, 1);
        const Eigen::Matrix3d h = box.matrix();
        for (std::size_t k = 0; k < atoms; ++k) {
            const Eigen::Vector3d r = h * Eigen::Vector3d(u(random), u(random), u(random));
            xyz[3 * k] = r.x();
            xyz[3 * k + 1] = r.y();
            xyz[3 * k + 2] = r.z();
        }
    }
    const double before = status_bytes("VmRSS:");
    tricell::NeighborList list;
    tricell::NeighborSearch search;
    try {
        search.build(box, tricell::PointsView(xyz.data(), atoms), options);
        const double built = status_bytes("VmRSS:");
        search.compute(list);
        const double peak = peak_bytes();
        const tricell::PairColumns& c = list.columns();
        const double returned =
            double(c.i.size() * 4 + c.j.size() * 4 + c.shifts.size() * 4 + c.distances.size() * 8 +
                   c.vectors.size() * 8 + c.offsets.size() * 8);
        // The list's peak by the library's model (docs/memory.md), what max_bytes bounds.
        const double list_peak =
            tricell::detail::list_memory(options).peak(double(list.size()), atoms);
        const double per_pair = returned / double(std::max<std::size_t>(1, list.size()));
        const double model = built + 1.2 * list_peak;
        std::printf("atoms %zu cutoff %g %s threads %d quantities %s order %s\n", atoms, cutoff,
                    options.half ? "half" : "full", options.threads, quantities.c_str(),
                    options.sorted    ? "sorted"
                    : options.grouped ? "grouped"
                                      : "none");
        std::printf("pairs %zu (estimated %.4g), returned arrays %.3f GiB (%.1f bytes/pair)\n",
                    list.size(), search.estimated_pairs(), gib(returned), per_pair);
        std::printf("RSS: positions %.3f GiB, after build %.3f GiB (build's O(N) %.3f GiB)\n",
                    gib(before), gib(built), gib(built - before));
        std::printf("model's list peak %.3f GiB (max_bytes %.3f GiB)\n", gib(list_peak),
                    gib(double(options.max_bytes)));
        std::printf("peak RSS %.3f GiB; peak - after build = %.3f x returned arrays = %.3f x the "
                    "model's list peak; bound %.3f GiB: %s\n",
                    gib(peak), (peak - built) / returned, (peak - built) / list_peak, gib(model),
                    peak <= model ? "within" : "OVER");
    } catch (const tricell::Error& e) {
        std::printf("atoms %zu cutoff %g quantities %s refused: %s\n", atoms, cutoff,
                    quantities.c_str(), e.what());
        std::printf("RSS: positions %.3f GiB, peak RSS %.3f GiB (peak - positions %.3f GiB)\n",
                    gib(before), gib(peak_bytes()), gib(peak_bytes() - before));
    }
    return 0;
}
