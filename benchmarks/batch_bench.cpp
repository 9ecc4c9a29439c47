// batch_bench: many small structures (ML-potential batches), one call per structure against
// one compute_neighbors_batch() call, single- and two-threaded. Not a test: timings live here.
//
// The batch: 10^4 structures (--structures) of 2 to 64 atoms, random positions at 0.03 to
// 0.1 atoms/A^3 in random triclinic cells (angles 60 to 120 degrees), so most cells are
// smaller than the cutoff (5 A, --cutoff) in some direction. Full lists storing i, j, S, d.
// Prints one line per way of computing: median seconds over K rounds (--repeat), structures/s
// and pairs/s, and the speed-up over one compute_neighbors() call per structure (whose list is
// overwritten each time; the second line keeps every structure's pairs, as the batch does).
#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include <tricell/batch.hpp>
#include <tricell/neighbor_list.hpp>

namespace {

using Clock = std::chrono::steady_clock;

template <class Body> double median_seconds(Body&& body, int repeat) {
    body(); // warm-up
    std::vector<double> seconds;
    for (int k = 0; k < repeat; ++k) {
        const auto start = Clock::now();
        body();
        seconds.push_back(std::chrono::duration<double>(Clock::now() - start).count());
    }
    std::sort(seconds.begin(), seconds.end());
    return seconds[seconds.size() / 2];
}

} // namespace

int main(int argc, char** argv) {
    std::size_t count = 10000;
    double cutoff = 5;
    int repeat = 7;
    bool half = false;
    for (int a = 1; a < argc; ++a) {
        const std::string arg = argv[a];
        if (arg == "--structures" && a + 1 < argc) {
            count = std::size_t(std::atol(argv[++a]));
        } else if (arg == "--cutoff" && a + 1 < argc) {
            cutoff = std::atof(argv[++a]);
        } else if (arg == "--repeat" && a + 1 < argc) {
            repeat = std::max(1, std::atoi(argv[++a]));
        } else if (arg == "--half") {
            half = true;
        } else {
            std::fprintf(stderr, "usage: batch_bench [--structures N] [--cutoff R] [--repeat K] "
                                 "[--half]\n");
            return 2;
        }
    }

    std::mt19937_64 rng(2026);
    std::uniform_real_distribution<double> unit(0, 1);
    std::vector<tricell::Box> boxes;
    std::vector<std::vector<Eigen::Vector3d>> positions(count);
    std::size_t atoms = 0;
    for (std::size_t s = 0; s < count; ++s) {
        const int n = 2 + int(unit(rng) * 63);
        const double density = 0.03 + 0.07 * unit(rng);
        const double alpha = 60 + 60 * unit(rng), beta = 60 + 60 * unit(rng),
                     gamma = 60 + 60 * unit(rng);
        tricell::Box shape = tricell::Box::from_parameters(1, 1, 1, 90, 90, 90);
        try {
            shape =
                tricell::Box::from_parameters(1, 1 + unit(rng), 1 + unit(rng), alpha, beta, gamma);
        } catch (const std::exception&) { // impossible angles: keep the cube
        }
        const double scale = std::cbrt(n / density / shape.volume());
        const tricell::LatticeParameters p = shape.parameters();
        boxes.push_back(tricell::Box::from_parameters(p.a * scale, p.b * scale, p.c * scale,
                                                      p.alpha, p.beta, p.gamma));
        for (int i = 0; i < n; ++i) {
            positions[s].push_back(boxes.back().matrix() *
                                   Eigen::Vector3d(unit(rng), unit(rng), unit(rng)));
        }
        atoms += std::size_t(n);
    }
    std::vector<tricell::BatchStructure> batch;
    for (std::size_t s = 0; s < count; ++s) {
        batch.push_back(tricell::BatchStructure{boxes[s], positions[s]});
    }

    tricell::NeighborOptions options;
    options.cutoff = cutoff;
    options.half = half;
    tricell::NeighborList list;
    std::size_t pairs = 0;
    const double loop = median_seconds(
        [&] {
            pairs = 0;
            for (std::size_t s = 0; s < count; ++s) {
                tricell::compute_neighbors(boxes[s], positions[s], options, list);
                pairs += list.size();
            }
        },
        repeat);
    std::printf("# %zu structures, %zu atoms, cutoff %g, %s list, %zu pairs; median of %d\n", count,
                atoms, cutoff, half ? "half" : "full", pairs, repeat);
    std::printf("%-36s %10s %14s %12s %8s\n", "way", "seconds", "structures/s", "M pairs/s",
                "speed-up");
    auto report = [&](const char* way, double seconds) {
        std::printf("%-36s %10.4f %14.0f %12.1f %8.2f\n", way, seconds, double(count) / seconds,
                    double(pairs) / seconds / 1e6, loop / seconds);
    };
    report("one compute_neighbors() per structure", loop);
    // The same loop keeping every structure's pairs (appended to shared columns, as the batch
    // stores them): the loop above overwrites one small list that stays in cache.
    std::vector<std::uint32_t> keep_i, keep_j;
    std::vector<std::int32_t> keep_s;
    std::vector<double> keep_d;
    std::vector<std::size_t> keep_offsets;
    const double kept = median_seconds(
        [&] {
            keep_i.clear();
            keep_j.clear();
            keep_s.clear();
            keep_d.clear();
            keep_offsets.assign(1, 0);
            for (std::size_t s = 0; s < count; ++s) {
                tricell::compute_neighbors(boxes[s], positions[s], options, list);
                keep_i.insert(keep_i.end(), list.i().begin(), list.i().end());
                keep_j.insert(keep_j.end(), list.j().begin(), list.j().end());
                keep_s.insert(keep_s.end(), list.shifts().begin(), list.shifts().end());
                keep_d.insert(keep_d.end(), list.distances().begin(), list.distances().end());
                keep_offsets.push_back(keep_i.size());
            }
        },
        repeat);
    report("one call per structure, pairs kept", kept);
    tricell::BatchList out;
    for (int threads : {1, 2}) {
        options.threads = threads;
        const double seconds =
            median_seconds([&] { tricell::compute_neighbors_batch(batch, options, out); }, repeat);
        if (out.size() != pairs) {
            std::fprintf(stderr, "batch_bench: the batch has %zu pairs, the loop %zu\n", out.size(),
                         pairs);
            return 1;
        }
        report(threads == 1 ? "compute_neighbors_batch, 1 thread"
                            : "compute_neighbors_batch, 2 threads",
               seconds);
    }
    return 0;
}
