// vesin_peer: times vesin's CPU neighbour list (its C API, vesin_neighbors) on a structure
// file, as a peer in benchmarks/compare. Built only when CMake is given a vesin checkout
// (-DTRICELL_VESIN_DIR=...; see benchmarks/README.md). The structure is read with tricell::io
// so that both libraries see identical positions. Like `tricell bench`: one warm-up call, then
// K timed calls into the same reused VesinNeighborList, storing i, j, S and d, Verlet caching
// off (skin 0), so every call does the whole search.
//
// usage: vesin_peer FILE CUTOFF [REPEAT] [--half] [--threads T]
// prints: pairs=<pairs> median_s=<seconds> min_s=<seconds>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include <vesin.h>

#include <tricell/io/structure.hpp>

int main(int argc, char** argv) {
    if (argc < 3) {
        std::fprintf(stderr, "usage: vesin_peer FILE CUTOFF [REPEAT] [--half] [--threads T]\n");
        return 2;
    }
    const double cutoff = std::atof(argv[2]);
    int repeat = 5;
    bool half = false;
    int threads = 1;
    for (int a = 3; a < argc; ++a) {
        const std::string arg = argv[a];
        if (arg == "--half") {
            half = true;
        } else if (arg == "--threads" && a + 1 < argc) {
            threads = std::atoi(argv[++a]);
        } else {
            repeat = std::max(1, std::atoi(argv[a]));
        }
    }
    tricell::io::Structure structure;
    try {
        structure = tricell::io::read_structure(argv[1]);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "vesin_peer: %s\n", e.what());
        return 1;
    }
    // vesin takes the lattice vectors as rows; tricell's matrix has them as columns.
    const Eigen::Matrix3d& h = structure.box.matrix();
    double box[3][3];
    bool periodic[3];
    for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) {
            box[r][c] = h(c, r);
        }
        periodic[r] = structure.box.periodic(r);
    }
    std::vector<double> points(3 * structure.size());
    for (std::size_t k = 0; k < structure.size(); ++k) {
        for (int c = 0; c < 3; ++c) {
            points[3 * k + std::size_t(c)] = structure.positions[k][c];
        }
    }

    VesinOptions options{};
    options.cutoff = cutoff;
    options.full = !half;
    options.sorted = false;
    options.algorithm = VesinAutoAlgorithm;
    options.n_threads = threads;
    options.return_shifts = true;
    options.return_distances = true;
    options.return_vectors = false;
    options.skin = 0;
    VesinDevice cpu{VesinCPU, 0};
    VesinNeighborList list;
    std::vector<double> seconds;
    for (int run = 0; run <= repeat; ++run) { // run 0 is the warm-up
        const char* error = nullptr;
        const auto start = std::chrono::steady_clock::now();
        const int status =
            vesin_neighbors(reinterpret_cast<const double(*)[3]>(points.data()), structure.size(),
                            box, periodic, cpu, options, &list, &error);
        const auto stop = std::chrono::steady_clock::now();
        if (status != 0) {
            std::fprintf(stderr, "vesin_peer: %s\n", error != nullptr ? error : "vesin failed");
            return 1;
        }
        if (run > 0) {
            seconds.push_back(std::chrono::duration<double>(stop - start).count());
        }
    }
    std::sort(seconds.begin(), seconds.end());
    std::printf("pairs=%zu median_s=%.6g min_s=%.6g\n", list.length, seconds[seconds.size() / 2],
                seconds.front());
    vesin_free(&list);
    return 0;
}
