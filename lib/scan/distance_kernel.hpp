// The innermost loop of the neighbour search: which points of a contiguous struct-of-arrays
// range lie within the cutoff of one point. Compiled once per instruction set in the library
// and chosen at run time (AVX-512 or AVX2 where the processor has it, portable C++ otherwise), so
// the default build stays portable. Every version rounds the same operations in the same order,
// without fused multiply-adds, so their results are bit for bit the same: the difference vector
// is (x_b - x_a) + T, the positions' difference first and then the Cartesian image translation
// T, and d^2 = dx*dx + dy*dy + dz*dz. In that order the pair seen from b through -T has exactly
// the negated vector (IEEE rounding is symmetric: fl(p - q) = -fl(q - p)) and the same d^2, so a
// half list turns pairs around without computing anything again.
#pragma once

#include <cstdint>
#include <vector>

#include "tricell/export.hpp"

namespace tricell::detail {

/// Largest `count` within_cutoff() accepts.
constexpr std::uint32_t kernel_block = 64;
/// Slots past the last hit that a kernel may write (it stores whole vectors): `hits` and
/// `hit_d_sq` need count + kernel_slack slots.
constexpr std::uint32_t kernel_slack = 8;

/// For k in [0, count), with D = ((x[k] - ax) + shift[0], (y[k] - ay) + shift[1],
/// (z[k] - az) + shift[2]): if |D|^2 < cutoff_sq, appends k to hits and |D|^2 to hit_d_sq.
/// Returns the number of hits. count <= kernel_block.
std::uint32_t within_cutoff(const double* x, const double* y, const double* z, std::uint32_t count,
                            double ax, double ay, double az, const double* shift, double cutoff_sq,
                            std::uint32_t* hits, double* hit_d_sq);

/// Largest number of points within_cutoff_group() takes on its own side.
constexpr std::uint32_t kernel_group = 8;

/// within_cutoff() for `group` points (ax[g], ay[g], az[g]) against the same range through the
/// same shift in one call,
/// g in order: hit k of point g is appended as g * kernel_block + k. A cell of a few atoms
/// against a row of its neighbours is one call instead of one per atom (the per-call cost
/// was as large as the tests on diamond Si, whose rows hold ~20 atoms). group <=
/// kernel_group, count <= kernel_block; hits and hit_d_sq need group * count + kernel_slack
/// slots.
std::uint32_t within_cutoff_group(const double* x, const double* y, const double* z,
                                  std::uint32_t count, const double* ax, const double* ay,
                                  const double* az, std::uint32_t group, const double* shift,
                                  double cutoff_sq, std::uint32_t* hits, double* hit_d_sq);

/// The direct backend's test of one pair through many images: for k in [0, count), with
/// D = (d0[0] + vx[k], d0[1] + vy[k], d0[2] + vz[k]) (d0 = x_b - x_a, so D is the (x_b - x_a) + T
/// of the other kernels): if |D|^2 < cutoff_sq, appends k to hits and |D|^2 to hit_d_sq.
/// Returns the number of hits; hits and hit_d_sq need count + kernel_slack slots.
std::uint32_t within_images(const double* vx, const double* vy, const double* vz,
                            std::uint32_t count, const double* d0, double cutoff_sq,
                            std::uint32_t* hits, double* hit_d_sq);

/// One instruction set's within_cutoff(), within_cutoff_group() and within_images() (AVX2 has
/// no within_images() of its own: the portable loop).
struct DistanceKernel {
    const char* name; ///< "avx512", "avx2" or "generic"
    std::uint32_t (*one)(const double*, const double*, const double*, std::uint32_t, double, double,
                         double, const double*, double, std::uint32_t*, double*);
    std::uint32_t (*group)(const double*, const double*, const double*, std::uint32_t,
                           const double*, const double*, const double*, std::uint32_t,
                           const double*, double, std::uint32_t*, double*);
    std::uint32_t (*images)(const double*, const double*, const double*, std::uint32_t,
                            const double*, double, std::uint32_t*, double*);
};

/// Every kernel this processor can run, fastest first: the first is the one within_cutoff()
/// and within_cutoff_group() use, the last the portable one (for tests, which hold each to the
/// portable one bit for bit).
std::vector<DistanceKernel> distance_kernels();

/// out[k] = sqrt(in[k]) for k in [0, count), four at a time where the processor has AVX (sqrt is
/// correctly rounded either way, so the results are the same bits; a scalar loop calls the
/// library's sqrt once per value, and was a tenth of a full list's time on diamond Si).
void square_roots(const double* in, std::uint32_t count, double* out);

/// The threshold T with d_sq < T exactly when sqrt(d_sq) < cutoff (for every double d_sq), so
/// the strict cutoff of the contract holds to the last bit and for tiny cutoffs whose square
/// underflows. Requires a finite cutoff > 0. (Exported for tricell::mpi's Verlet list.)
TRICELL_API double strict_threshold_sq(double cutoff);

/// Name of the kernel chosen on this processor ("avx512", "avx2" or "generic").
const char* distance_kernel_name();

} // namespace tricell::detail
