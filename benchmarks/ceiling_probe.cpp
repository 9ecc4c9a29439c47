// ceiling_probe: what the machine allows for one neighbour-list workload, measured in the same
// run as the workload itself (benchmarks/compare runs it right after `tricell bench`).
//
// A neighbour list has two unavoidable costs: testing every candidate pair the stencil generates
// against the cutoff, and writing every pair found. The probe times each of them alone, with
// nothing else in the way:
//
// - store: writing P records (i, j, S, d; 28 bytes) into arrays already allocated and touched
//   (a reused list), one sequential pass per column, P = the workload's pair count;
// - test: the library's own run-time selected distance kernel of the general scan (AVX2 with lane
//   compaction where the processor has it; the search's range kernel stores its hits directly)
//   over C candidates in full 64-candidate blocks held in L1, C = the
//   distance tests the search itself makes for the workload (NeighborSearch::unit_work, what
//   its stencil and clusters leave to test). The block points are placed so that the hit
//   fraction matches P / C.
//
// ceiling_s = store_s + test_s is the time of a search with no overhead at all: no binning, no
// loop control between ranges, no image bookkeeping, no call overhead. A workload's time as a
// fraction of it says how much of the work is the work itself.
//
// usage: ceiling_probe FILE --cutoff R [--half] [--repeat K]
// prints "key value" lines: pairs, candidates, store_s, test_s, ceiling_s (medians of K), and
// store_streaming_s (the same records with non-temporal stores, for comparison; 0 without AVX2)
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "scan/distance_kernel.hpp"
#include <tricell/io/structure.hpp>
#include <tricell/neighbor_list.hpp>

namespace {

using Clock = std::chrono::steady_clock;

// Runs body() `inner` times per sample, K samples after a warm-up, and returns the median time
// of one body() call. `inner` grows until one sample lasts at least 2 ms.
template <class Body> double median_time(Body&& body, int repeat) {
    body();
    long inner = 1;
    for (;;) {
        const auto start = Clock::now();
        for (long r = 0; r < inner; ++r) {
            body();
        }
        if (std::chrono::duration<double>(Clock::now() - start).count() > 2e-3 || inner > 1e7) {
            break;
        }
        inner *= 4;
    }
    std::vector<double> samples;
    for (int k = 0; k < repeat; ++k) {
        const auto start = Clock::now();
        for (long r = 0; r < inner; ++r) {
            body();
        }
        samples.push_back(std::chrono::duration<double>(Clock::now() - start).count() /
                          double(inner));
    }
    std::sort(samples.begin(), samples.end());
    return samples[samples.size() / 2];
}

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
#define TRICELL_PROBE_STREAMING 1
// The same records written with non-temporal (streaming) stores, 8 pairs per step, into
// 32-byte aligned columns: no read-for-ownership of the destination lines. Not a ceiling the
// library is held to (it needs whole 64-byte lines per column), but what storing could cost if
// it streamed; benchmarks/compare reports it beside store_s for the lead.
__attribute__((target("avx2"))) void store_streaming(std::uint32_t* pi, std::uint32_t* pj,
                                                     std::int32_t* ps, double* pd,
                                                     std::size_t pairs) {
    const __m256i lanes = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
    for (std::size_t k = 0; k + 8 <= pairs; k += 8) {
        const __m256i kk = _mm256_add_epi32(_mm256_set1_epi32(int(k)), lanes);
        _mm256_stream_si256(reinterpret_cast<__m256i*>(pi + k), _mm256_srli_epi32(kk, 5));
        _mm256_stream_si256(reinterpret_cast<__m256i*>(pj + k),
                            _mm256_mullo_epi32(kk, _mm256_set1_epi32(7)));
        for (int w = 0; w < 3; ++w) {
            _mm256_stream_si256(reinterpret_cast<__m256i*>(ps + 3 * k + 8 * std::size_t(w)),
                                _mm256_and_si256(kk, _mm256_set1_epi32(1 << w)));
        }
        const __m256d d =
            _mm256_mul_pd(_mm256_cvtepi32_pd(_mm256_castsi256_si128(kk)), _mm256_set1_pd(1e-9));
        _mm256_stream_pd(pd + k, d);
        _mm256_stream_pd(pd + k + 4, d);
    }
    _mm_sfence();
}

template <class T> T* aligned_array(std::size_t count) {
    const std::size_t bytes = (count * sizeof(T) + 63) / 64 * 64;
    return static_cast<T*>(std::aligned_alloc(64, bytes == 0 ? 64 : bytes));
}
#endif

} // namespace

int main(int argc, char** argv) {
    std::string file;
    double cutoff = 0;
    bool half = false;
    int repeat = 7;
    for (int a = 1; a < argc; ++a) {
        const std::string arg = argv[a];
        if (arg == "--cutoff" && a + 1 < argc) {
            cutoff = std::atof(argv[++a]);
        } else if (arg == "--repeat" && a + 1 < argc) {
            repeat = std::max(1, std::atoi(argv[++a]));
        } else if (arg == "--half") {
            half = true;
        } else if (file.empty() && arg[0] != '-') {
            file = arg;
        } else {
            std::fprintf(stderr, "usage: ceiling_probe FILE --cutoff R [--half] [--repeat K]\n");
            return 2;
        }
    }
    if (file.empty() || !(cutoff > 0)) {
        std::fprintf(stderr, "usage: ceiling_probe FILE --cutoff R [--half] [--repeat K]\n");
        return 2;
    }

    tricell::NeighborOptions options;
    options.cutoff = cutoff;
    options.half = half;
    tricell::NeighborSearch search;
    tricell::NeighborList list;
    double candidates = 0;
    try {
        const tricell::io::Structure structure = tricell::io::read_structure(file);
        search.build(structure.box, structure.positions, options);
        search.compute(list);
        for (const double unit : search.unit_work().measured) {
            candidates += unit;
        }
    } catch (const std::exception& e) {
        std::fprintf(stderr, "ceiling_probe: %s\n", e.what());
        return 1;
    }
    const std::size_t pairs = list.size();

    // Store: P records into reused memory (touched by the warm-up call of median_time).
    std::vector<std::uint32_t> is(pairs), js(pairs);
    std::vector<std::int32_t> ss(3 * pairs);
    std::vector<double> ds(pairs);
    const double store_s = median_time(
        [&] {
            std::uint32_t* pi = is.data();
            std::uint32_t* pj = js.data();
            std::int32_t* ps = ss.data();
            double* pd = ds.data();
            for (std::size_t k = 0; k < pairs; ++k) {
                pi[k] = std::uint32_t(k >> 5);
                pj[k] = std::uint32_t(k * 7);
                ps[3 * k] = std::int32_t(k & 1);
                ps[3 * k + 1] = -std::int32_t(k & 2);
                ps[3 * k + 2] = std::int32_t(k & 4);
                pd[k] = double(k) * 1e-9;
            }
            asm volatile("" : : "r"(pi), "r"(pj), "r"(ps), "r"(pd) : "memory");
        },
        repeat);

    double streaming_s = 0;
#ifdef TRICELL_PROBE_STREAMING
    __builtin_cpu_init();
    if (__builtin_cpu_supports("avx2")) {
        std::uint32_t* si = aligned_array<std::uint32_t>(pairs);
        std::uint32_t* sj = aligned_array<std::uint32_t>(pairs);
        std::int32_t* sss = aligned_array<std::int32_t>(3 * pairs);
        double* sd = aligned_array<double>(pairs);
        streaming_s = median_time([&] { store_streaming(si, sj, sss, sd, pairs); }, repeat);
        std::free(si);
        std::free(sj);
        std::free(sss);
        std::free(sd);
    }
#endif

    // Test: C candidates in blocks of 64 points from 16 blocks (24 KB, L1-resident), points in a
    // cube of side 1 around the query, radius chosen so the hit fraction is about P / C.
    constexpr std::uint32_t block = tricell::detail::kernel_block;
    constexpr std::uint32_t blocks = 16;
    std::vector<double> x(block * blocks), y(block * blocks), z(block * blocks);
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u(-0.5, 0.5);
    for (std::size_t k = 0; k < x.size(); ++k) {
        x[k] = u(rng);
        y[k] = u(rng);
        z[k] = u(rng);
    }
    const double fraction = candidates > 0 ? std::min(0.52, double(pairs) / candidates) : 0.0;
    const double radius = std::cbrt(3 * fraction / (4 * M_PI));
    const double radius_sq = radius * radius;
    const std::size_t calls = std::size_t(std::ceil(candidates / block));
    std::uint32_t hits[block + tricell::detail::kernel_slack];
    double hit_d_sq[block + tricell::detail::kernel_slack];
    std::uint64_t found = 0;
    const double shift[3] = {0.5, -0.5, 0.25};
    const double test_s = median_time(
        [&] {
            for (std::size_t c = 0; c < calls; ++c) {
                const std::size_t b = (c % blocks) * block;
                const double q = 1e-3 * double(c % 7);
                found +=
                    tricell::detail::within_cutoff(x.data() + b, y.data() + b, z.data() + b, block,
                                                   q, -q, q, shift, radius_sq, hits, hit_d_sq);
            }
        },
        repeat);
    if (found == 1) {
        std::printf("# unlikely\n");
    }

    std::printf("pairs %zu\n", pairs);
    std::printf("candidates %.0f\n", candidates);
    std::printf("kernel %s\n", tricell::detail::distance_kernel_name());
    std::printf("store_s %.6g\n", store_s);
    std::printf("test_s %.6g\n", test_s);
    std::printf("ceiling_s %.6g\n", store_s + test_s);
    std::printf("store_streaming_s %.6g\n", streaming_s);
    return 0;
}
