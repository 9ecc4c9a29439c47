// Neighbour-list build + search throughput (Google Benchmark). Not a test: timings live here.
//
// Workloads: diamond Si supercells (a = 5.43 A, cutoff 5 A, 64 to 32768 atoms) and a
// random triclinic box at 0.1 atoms/A^3 (cutoff 6 A, 1e3 to 1e5 atoms); full and half lists,
// sorted and linked cell lists, stored (i, j, S, d) and the visitor that stores nothing.
// Each reports pairs per second ("pairs/s") over the whole call: grid, cell list and search.
#include <cmath>
#include <random>
#include <vector>

#include <benchmark/benchmark.h>

#include <tricell/tricell.hpp>

namespace {

struct System {
    tricell::Box box = tricell::Box::from_parameters(1, 1, 1, 90, 90, 90);
    std::vector<Eigen::Vector3d> positions;
};

System diamond_si(int cells) {
    const double a = 5.43;
    System sys;
    sys.box = tricell::Box::from_parameters(a * cells, a * cells, a * cells, 90, 90, 90);
    const double basis[8][3] = {{0, 0, 0},       {0, .5, .5},     {.5, 0, .5},     {.5, .5, 0},
                                {.25, .25, .25}, {.25, .75, .75}, {.75, .25, .75}, {.75, .75, .25}};
    for (int i = 0; i < cells; ++i) {
        for (int j = 0; j < cells; ++j) {
            for (int k = 0; k < cells; ++k) {
                for (const auto& b : basis) {
                    sys.positions.emplace_back(a * (i + b[0]), a * (j + b[1]), a * (k + b[2]));
                }
            }
        }
    }
    return sys;
}

System random_triclinic(int atoms) {
    // Triclinic shape (alpha 80, beta 100, gamma 110 degrees) scaled to 0.1 atoms/A^3.
    const tricell::Box unit = tricell::Box::from_parameters(1.0, 1.1, 0.9, 80, 100, 110);
    const double scale = std::cbrt(atoms / 0.1 / unit.volume());
    System sys;
    sys.box = tricell::Box::from_parameters(scale, 1.1 * scale, 0.9 * scale, 80, 100, 110);
    std::mt19937_64 rng(42);
    std::uniform_real_distribution<double> u(0, 1);
    for (int i = 0; i < atoms; ++i) {
        sys.positions.push_back(sys.box.matrix() * Eigen::Vector3d(u(rng), u(rng), u(rng)));
    }
    return sys;
}

// range(0): size parameter; range(1): half (0/1); range(2): backend (0 dense, 1 linked)
template <System (*Make)(int), int Cutoff> void bm_stored(benchmark::State& state) {
    const System sys = Make(static_cast<int>(state.range(0)));
    tricell::NeighborOptions options;
    options.cutoff = Cutoff;
    options.half = state.range(1) != 0;
    options.backend =
        state.range(2) == 0 ? tricell::SearchBackend::dense : tricell::SearchBackend::linked;
    tricell::NeighborList list;
    for (auto _ : state) {
        tricell::compute_neighbors(sys.box, sys.positions, options, list);
        benchmark::DoNotOptimize(list.distances().data());
    }
    state.counters["atoms"] = double(sys.positions.size());
    state.counters["pairs"] = double(list.size());
    state.counters["pairs/s"] =
        benchmark::Counter(double(list.size()), benchmark::Counter::kIsIterationInvariantRate);
}

template <System (*Make)(int), int Cutoff> void bm_visitor(benchmark::State& state) {
    const System sys = Make(static_cast<int>(state.range(0)));
    tricell::NeighborOptions options;
    options.cutoff = Cutoff;
    options.half = state.range(1) != 0;
    std::size_t pairs = 0;
    for (auto _ : state) {
        pairs = 0;
        double sum = 0;
        tricell::for_each_pair(sys.box, sys.positions, options, [&](const tricell::Pair& p) {
            ++pairs;
            sum += p.distance_sq;
        });
        benchmark::DoNotOptimize(sum);
    }
    state.counters["atoms"] = double(sys.positions.size());
    state.counters["pairs"] = double(pairs);
    state.counters["pairs/s"] =
        benchmark::Counter(double(pairs), benchmark::Counter::kIsIterationInvariantRate);
}

void diamond_args(benchmark::internal::Benchmark* b) {
    for (const int cells : {2, 4, 8, 16}) {
        for (const int half : {0, 1}) {
            for (const int linked : {0, 1}) {
                b->Args({cells, half, linked});
            }
        }
    }
    b->ArgNames({"cells", "half", "linked"})->Unit(benchmark::kMillisecond);
}

void random_args(benchmark::internal::Benchmark* b) {
    for (const int atoms : {1000, 10000, 100000}) {
        for (const int half : {0, 1}) {
            for (const int linked : {0, 1}) {
                b->Args({atoms, half, linked});
            }
        }
    }
    b->ArgNames({"atoms", "half", "linked"})->Unit(benchmark::kMillisecond);
}

void visitor_args(benchmark::internal::Benchmark* b, std::initializer_list<int> sizes,
                  const char* name) {
    for (const int size : sizes) {
        for (const int half : {0, 1}) {
            b->Args({size, half});
        }
    }
    b->ArgNames({name, "half"})->Unit(benchmark::kMillisecond);
}

} // namespace

BENCHMARK(bm_stored<diamond_si, 5>)->Name("diamond_si/stored")->Apply(diamond_args);
BENCHMARK(bm_stored<random_triclinic, 6>)->Name("random_triclinic/stored")->Apply(random_args);
BENCHMARK(bm_visitor<diamond_si, 5>)->Name("diamond_si/visitor")->Apply([](auto* b) {
    visitor_args(b, {8, 16}, "cells");
});
BENCHMARK(bm_visitor<random_triclinic, 6>)->Name("random_triclinic/visitor")->Apply([](auto* b) {
    visitor_args(b, {10000, 100000}, "atoms");
});

BENCHMARK_MAIN();
