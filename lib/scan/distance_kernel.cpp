#include "scan/distance_kernel.hpp"

#include <cmath>

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define TRICELL_HAVE_AVX2_KERNEL 1
#include <immintrin.h>
#endif

namespace tricell::detail {

namespace {

// Portable version: a vectorisable distance loop, then a branch-free compaction (the index is
// always written, the count advances only on a hit).
// (Hit k is recorded as label + k.)
std::uint32_t within_cutoff_generic(const double* x, const double* y, const double* z,
                                    std::uint32_t count, double ax, double ay, double az,
                                    const double* shift, double cutoff_sq, std::uint32_t* hits,
                                    double* hit_d_sq, std::uint32_t label) {
    const double vx = shift[0], vy = shift[1], vz = shift[2];
    double d_sq[kernel_block];
    for (std::uint32_t k = 0; k < count; ++k) {
        const double dx = (x[k] - ax) + vx, dy = (y[k] - ay) + vy, dz = (z[k] - az) + vz;
        d_sq[k] = dx * dx + dy * dy + dz * dz;
    }
    std::uint32_t found = 0;
    for (std::uint32_t k = 0; k < count; ++k) {
        hits[found] = label + k;
        hit_d_sq[found] = d_sq[k];
        found += d_sq[k] < cutoff_sq ? 1u : 0u;
    }
    return found;
}

std::uint32_t within_cutoff_one_generic(const double* x, const double* y, const double* z,
                                        std::uint32_t count, double ax, double ay, double az,
                                        const double* shift, double cutoff_sq, std::uint32_t* hits,
                                        double* hit_d_sq) {
    return within_cutoff_generic(x, y, z, count, ax, ay, az, shift, cutoff_sq, hits, hit_d_sq, 0);
}

std::uint32_t within_cutoff_group_generic(const double* x, const double* y, const double* z,
                                          std::uint32_t count, const double* ax, const double* ay,
                                          const double* az, std::uint32_t group,
                                          const double* shift, double cutoff_sq,
                                          std::uint32_t* hits, double* hit_d_sq) {
    std::uint32_t found = 0;
    for (std::uint32_t g = 0; g < group; ++g) {
        found += within_cutoff_generic(x, y, z, count, ax[g], ay[g], az[g], shift, cutoff_sq,
                                       hits + found, hit_d_sq + found, g * kernel_block);
    }
    return found;
}

#ifdef TRICELL_HAVE_AVX2_KERNEL

// Lane order that moves the set lanes of a 4-bit mask to the front, as 32-bit lane indices for
// doubles (two lanes each) and as plain positions for the indices.
struct CompressTables {
    alignas(32) std::int32_t doubles[16][8];
    alignas(16) std::int32_t positions[16][4];
    CompressTables() {
        for (int mask = 0; mask < 16; ++mask) {
            int n = 0;
            for (int lane = 0; lane < 4; ++lane) {
                if (mask & (1 << lane)) {
                    positions[mask][n] = lane;
                    doubles[mask][2 * n] = 2 * lane;
                    doubles[mask][2 * n + 1] = 2 * lane + 1;
                    ++n;
                }
            }
            for (; n < 4; ++n) {
                positions[mask][n] = 0;
                doubles[mask][2 * n] = 0;
                doubles[mask][2 * n + 1] = 1;
            }
        }
    }
};

const CompressTables compress_tables;

// AVX2: four distances at a time (mul and add, no FMA, same order as the generic loop), then the
// hits are compressed with a lane permutation from a 16-entry table: no branch per hit.
// (Hit k is recorded as label + k.)
template <bool Shifted>
__attribute__((target("avx2"))) inline std::uint32_t
within_cutoff_avx2(const double* x, const double* y, const double* z, std::uint32_t count,
                   double ax, double ay, double az, const double* shift, double cutoff_sq,
                   std::uint32_t* hits, double* hit_d_sq, std::uint32_t label) {
    const __m256d vax = _mm256_set1_pd(ax), vay = _mm256_set1_pd(ay), vaz = _mm256_set1_pd(az);
    const __m256d vvx = _mm256_set1_pd(shift[0]), vvy = _mm256_set1_pd(shift[1]),
                  vvz = _mm256_set1_pd(shift[2]);
    const __m256d vcut = _mm256_set1_pd(cutoff_sq);
    std::uint32_t found = 0;
    std::uint32_t k = 0;
    for (; k + 4 <= count; k += 4) {
        __m256d dx = _mm256_sub_pd(_mm256_loadu_pd(x + k), vax);
        __m256d dy = _mm256_sub_pd(_mm256_loadu_pd(y + k), vay);
        __m256d dz = _mm256_sub_pd(_mm256_loadu_pd(z + k), vaz);
        if constexpr (Shifted) {
            dx = _mm256_add_pd(dx, vvx);
            dy = _mm256_add_pd(dy, vvy);
            dz = _mm256_add_pd(dz, vvz);
        }
        const __m256d d_sq = _mm256_add_pd(
            _mm256_add_pd(_mm256_mul_pd(dx, dx), _mm256_mul_pd(dy, dy)), _mm256_mul_pd(dz, dz));
        const int mask = _mm256_movemask_pd(_mm256_cmp_pd(d_sq, vcut, _CMP_LT_OQ));
        const __m256i order =
            _mm256_load_si256(reinterpret_cast<const __m256i*>(compress_tables.doubles[mask]));
        _mm256_storeu_pd(hit_d_sq + found,
                         _mm256_castps_pd(_mm256_permutevar8x32_ps(_mm256_castpd_ps(d_sq), order)));
        const __m128i positions = _mm_add_epi32(
            _mm_load_si128(reinterpret_cast<const __m128i*>(compress_tables.positions[mask])),
            _mm_set1_epi32(static_cast<int>(label + k)));
        _mm_storeu_si128(reinterpret_cast<__m128i*>(hits + found), positions);
        found += static_cast<std::uint32_t>(__builtin_popcount(static_cast<unsigned>(mask)));
    }
    for (; k < count; ++k) {
        const double dx = (x[k] - ax) + shift[0], dy = (y[k] - ay) + shift[1],
                     dz = (z[k] - az) + shift[2];
        const double d_sq = dx * dx + dy * dy + dz * dz;
        hits[found] = label + k;
        hit_d_sq[found] = d_sq;
        found += d_sq < cutoff_sq ? 1u : 0u;
    }
    return found;
}

__attribute__((target("avx2"))) std::uint32_t
within_cutoff_one_avx2(const double* x, const double* y, const double* z, std::uint32_t count,
                       double ax, double ay, double az, const double* shift, double cutoff_sq,
                       std::uint32_t* hits, double* hit_d_sq) {
    return within_cutoff_avx2<true>(x, y, z, count, ax, ay, az, shift, cutoff_sq, hits, hit_d_sq,
                                    0);
}

__attribute__((target("avx2"))) std::uint32_t
within_cutoff_group_avx2(const double* x, const double* y, const double* z, std::uint32_t count,
                         const double* ax, const double* ay, const double* az, std::uint32_t group,
                         const double* shift, double cutoff_sq, std::uint32_t* hits,
                         double* hit_d_sq) {
    // A zero shift (most cell pairs of a large box) adds nothing: (x_b - x_a) + 0 and x_b - x_a
    // differ at most in the sign of a zero, which d^2 does not see.
    if (shift[0] == 0 && shift[1] == 0 && shift[2] == 0) {
        std::uint32_t found = 0;
        for (std::uint32_t g = 0; g < group; ++g) {
            found +=
                within_cutoff_avx2<false>(x, y, z, count, ax[g], ay[g], az[g], shift, cutoff_sq,
                                          hits + found, hit_d_sq + found, g * kernel_block);
        }
        return found;
    }
    std::uint32_t found = 0;
    for (std::uint32_t g = 0; g < group; ++g) {
        found += within_cutoff_avx2<true>(x, y, z, count, ax[g], ay[g], az[g], shift, cutoff_sq,
                                          hits + found, hit_d_sq + found, g * kernel_block);
    }
    return found;
}

// AVX-512: eight distances at a time, the hits compressed in registers (no table) and stored
// whole (kernel_slack), the last partial group through masked loads instead of a scalar tail
// (rows hold ~20 atoms on diamond Si, so the tail was a large part). Same operations in the
// same order as the other versions; the file is compiled without contraction into FMAs.
template <bool Shifted>
__attribute__((target("avx512f,avx512vl"))) inline std::uint32_t
within_cutoff_avx512(const double* x, const double* y, const double* z, std::uint32_t count,
                     double ax, double ay, double az, const double* shift, double cutoff_sq,
                     std::uint32_t* hits, double* hit_d_sq, std::uint32_t label) {
    const __m512d vax = _mm512_set1_pd(ax), vay = _mm512_set1_pd(ay), vaz = _mm512_set1_pd(az);
    const __m512d vvx = _mm512_set1_pd(shift[0]), vvy = _mm512_set1_pd(shift[1]),
                  vvz = _mm512_set1_pd(shift[2]);
    const __m512d vcut = _mm512_set1_pd(cutoff_sq);
    const __m256i lanes = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
    std::uint32_t found = 0;
    for (std::uint32_t k = 0; k < count; k += 8) {
        const __mmask8 valid = count - k >= 8 ? __mmask8(0xFF) : __mmask8((1u << (count - k)) - 1);
        __m512d dx = _mm512_sub_pd(_mm512_maskz_loadu_pd(valid, x + k), vax);
        __m512d dy = _mm512_sub_pd(_mm512_maskz_loadu_pd(valid, y + k), vay);
        __m512d dz = _mm512_sub_pd(_mm512_maskz_loadu_pd(valid, z + k), vaz);
        if constexpr (Shifted) {
            dx = _mm512_add_pd(dx, vvx);
            dy = _mm512_add_pd(dy, vvy);
            dz = _mm512_add_pd(dz, vvz);
        }
        const __m512d d_sq = _mm512_add_pd(
            _mm512_add_pd(_mm512_mul_pd(dx, dx), _mm512_mul_pd(dy, dy)), _mm512_mul_pd(dz, dz));
        const __mmask8 hit = _mm512_mask_cmp_pd_mask(valid, d_sq, vcut, _CMP_LT_OQ);
        _mm512_storeu_pd(hit_d_sq + found, _mm512_maskz_compress_pd(hit, d_sq));
        const __m256i positions =
            _mm256_add_epi32(lanes, _mm256_set1_epi32(static_cast<int>(label + k)));
        _mm256_storeu_si256(reinterpret_cast<__m256i*>(hits + found),
                            _mm256_maskz_compress_epi32(hit, positions));
        found += static_cast<std::uint32_t>(__builtin_popcount(hit));
    }
    return found;
}

__attribute__((target("avx512f,avx512vl"))) std::uint32_t
within_cutoff_one_avx512(const double* x, const double* y, const double* z, std::uint32_t count,
                         double ax, double ay, double az, const double* shift, double cutoff_sq,
                         std::uint32_t* hits, double* hit_d_sq) {
    return within_cutoff_avx512<true>(x, y, z, count, ax, ay, az, shift, cutoff_sq, hits, hit_d_sq,
                                      0);
}

__attribute__((target("avx512f,avx512vl"))) std::uint32_t
within_cutoff_group_avx512(const double* x, const double* y, const double* z, std::uint32_t count,
                           const double* ax, const double* ay, const double* az,
                           std::uint32_t group, const double* shift, double cutoff_sq,
                           std::uint32_t* hits, double* hit_d_sq) {
    // A zero shift (most cell pairs of a large box) adds nothing: (x_b - x_a) + 0 and x_b - x_a
    // differ at most in the sign of a zero, which d^2 does not see.
    if (shift[0] == 0 && shift[1] == 0 && shift[2] == 0) {
        std::uint32_t found = 0;
        for (std::uint32_t g = 0; g < group; ++g) {
            found +=
                within_cutoff_avx512<false>(x, y, z, count, ax[g], ay[g], az[g], shift, cutoff_sq,
                                            hits + found, hit_d_sq + found, g * kernel_block);
        }
        return found;
    }
    std::uint32_t found = 0;
    for (std::uint32_t g = 0; g < group; ++g) {
        found += within_cutoff_avx512<true>(x, y, z, count, ax[g], ay[g], az[g], shift, cutoff_sq,
                                            hits + found, hit_d_sq + found, g * kernel_block);
    }
    return found;
}

__attribute__((target("avx512f,avx512vl"))) std::uint32_t
within_images_avx512(const double* vx, const double* vy, const double* vz, std::uint32_t count,
                     const double* d0, double cutoff_sq, std::uint32_t* hits, double* hit_d_sq) {
    const __m512d cx = _mm512_set1_pd(d0[0]), cy = _mm512_set1_pd(d0[1]),
                  cz = _mm512_set1_pd(d0[2]), cut = _mm512_set1_pd(cutoff_sq);
    const __m256i step = _mm256_set1_epi32(8);
    __m256i k8 = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
    std::uint32_t found = 0;
    for (std::uint32_t k = 0; k < count; k += 8) {
        const __mmask8 valid = count - k >= 8 ? __mmask8(0xff) : __mmask8((1u << (count - k)) - 1);
        const __m512d dx = _mm512_add_pd(cx, _mm512_maskz_loadu_pd(valid, vx + k));
        const __m512d dy = _mm512_add_pd(cy, _mm512_maskz_loadu_pd(valid, vy + k));
        const __m512d dz = _mm512_add_pd(cz, _mm512_maskz_loadu_pd(valid, vz + k));
        const __m512d d_sq = _mm512_add_pd(
            _mm512_add_pd(_mm512_mul_pd(dx, dx), _mm512_mul_pd(dy, dy)), _mm512_mul_pd(dz, dz));
        const __mmask8 hit = _mm512_mask_cmp_pd_mask(valid, d_sq, cut, _CMP_LT_OQ);
        _mm256_storeu_si256(reinterpret_cast<__m256i*>(hits + found),
                            _mm256_maskz_compress_epi32(hit, k8));
        _mm512_storeu_pd(hit_d_sq + found, _mm512_maskz_compress_pd(hit, d_sq));
        found += std::uint32_t(__builtin_popcount(hit));
        k8 = _mm256_add_epi32(k8, step);
    }
    return found;
}

__attribute__((target("avx"))) void square_roots_avx(const double* in, std::uint32_t count,
                                                     double* out) {
    std::uint32_t k = 0;
    for (; k + 4 <= count; k += 4) {
        _mm256_storeu_pd(out + k, _mm256_sqrt_pd(_mm256_loadu_pd(in + k)));
    }
    for (; k < count; ++k) {
        _mm_store_sd(out + k, _mm_sqrt_sd(_mm_setzero_pd(), _mm_load_sd(in + k)));
    }
}

#endif

void square_roots_generic(const double* in, std::uint32_t count, double* out) {
    for (std::uint32_t k = 0; k < count; ++k) {
        out[k] = std::sqrt(in[k]);
    }
}

std::uint32_t within_images_generic(const double* vx, const double* vy, const double* vz,
                                    std::uint32_t count, const double* d0, double cutoff_sq,
                                    std::uint32_t* hits, double* hit_d_sq) {
    std::uint32_t found = 0;
    for (std::uint32_t k = 0; k < count; ++k) {
        const double dx = d0[0] + vx[k], dy = d0[1] + vy[k], dz = d0[2] + vz[k];
        const double d_sq = dx * dx + dy * dy + dz * dz;
        hits[found] = k;
        hit_d_sq[found] = d_sq;
        found += d_sq < cutoff_sq ? 1 : 0;
    }
    return found;
}

using SquareRoots = void (*)(const double*, std::uint32_t, double*);

SquareRoots choose_square_roots() {
#ifdef TRICELL_HAVE_AVX2_KERNEL
    __builtin_cpu_init();
    if (__builtin_cpu_supports("avx")) {
        return square_roots_avx;
    }
#endif
    return square_roots_generic;
}

const SquareRoots square_roots_kernel = choose_square_roots();

// The fastest this processor runs.
const DistanceKernel chosen = distance_kernels().front();

} // namespace

std::vector<DistanceKernel> distance_kernels() {
    std::vector<DistanceKernel> out;
#ifdef TRICELL_HAVE_AVX2_KERNEL
    __builtin_cpu_init();
    if (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl")) {
        out.push_back(
            {"avx512", within_cutoff_one_avx512, within_cutoff_group_avx512, within_images_avx512});
    }
    if (__builtin_cpu_supports("avx2")) {
        out.push_back(
            {"avx2", within_cutoff_one_avx2, within_cutoff_group_avx2, within_images_generic});
    }
#endif
    out.push_back(
        {"generic", within_cutoff_one_generic, within_cutoff_group_generic, within_images_generic});
    return out;
}

std::uint32_t within_cutoff(const double* x, const double* y, const double* z, std::uint32_t count,
                            double ax, double ay, double az, const double* shift, double cutoff_sq,
                            std::uint32_t* hits, double* hit_d_sq) {
    return chosen.one(x, y, z, count, ax, ay, az, shift, cutoff_sq, hits, hit_d_sq);
}

std::uint32_t within_cutoff_group(const double* x, const double* y, const double* z,
                                  std::uint32_t count, const double* ax, const double* ay,
                                  const double* az, std::uint32_t group, const double* shift,
                                  double cutoff_sq, std::uint32_t* hits, double* hit_d_sq) {
    return chosen.group(x, y, z, count, ax, ay, az, group, shift, cutoff_sq, hits, hit_d_sq);
}

std::uint32_t within_images(const double* vx, const double* vy, const double* vz,
                            std::uint32_t count, const double* d0, double cutoff_sq,
                            std::uint32_t* hits, double* hit_d_sq) {
    return chosen.images(vx, vy, vz, count, d0, cutoff_sq, hits, hit_d_sq);
}

void square_roots(const double* in, std::uint32_t count, double* out) {
    square_roots_kernel(in, count, out);
}

double strict_threshold_sq(double cutoff) {
    // The largest x with sqrt(x) < cutoff (sqrt is correctly rounded, hence monotonic), then
    // the next double above it.
    double x = cutoff * cutoff;
    while (x > 0 && std::sqrt(x) >= cutoff) {
        x = std::nextafter(x, 0.0);
    }
    while (std::sqrt(std::nextafter(x, HUGE_VAL)) < cutoff) {
        x = std::nextafter(x, HUGE_VAL);
    }
    return std::nextafter(x, HUGE_VAL);
}

const char* distance_kernel_name() {
    return chosen.name;
}

} // namespace tricell::detail
