#include <cmath>
#include <iterator>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "scan/distance_kernel.hpp"

using tricell::detail::kernel_block;

using tricell::detail::distance_kernels;
using tricell::detail::kernel_slack;

// Every kernel this processor can run (AVX-512, AVX2, the portable one) must agree bit for bit
// with the portable one, for every block length (the vector groups, the masked or scalar tail),
// with hits exactly at the cutoff, and the first of them is the one the search uses.
TEST(DistanceKernel, EveryKernelMatchesThePortableOneBitForBit) {
    const auto kernels = distance_kernels();
    ASSERT_EQ(std::string(kernels.front().name), tricell::detail::distance_kernel_name());
    ASSERT_EQ(std::string(kernels.back().name), "generic");
    for (const auto& kernel : kernels) {
        SCOPED_TRACE(kernel.name);
        std::mt19937_64 rng(17);
        std::uniform_real_distribution<double> u(-3, 3);
        for (int trial = 0; trial < 2000; ++trial) {
            const std::uint32_t count = std::uint32_t(trial) % (kernel_block + 1);
            const double ax = u(rng) / 3, ay = u(rng) / 3, az = u(rng) / 3;
            // A cell shift on every other trial (none on the rest: the plain difference).
            const double shift[3] = {trial % 2 ? u(rng) : 0.0, trial % 2 ? u(rng) : 0.0,
                                     trial % 2 ? u(rng) : 0.0};
            std::vector<double> x(count), y(count), z(count);
            for (std::uint32_t k = 0; k < count; ++k) {
                x[k] = u(rng), y[k] = u(rng), z[k] = u(rng);
            }
            if (count > 3) {
                x[1] = ax + 2.0, y[1] = ay, z[1] = az; // at the cutoff when unshifted: no hit
            }
            const double cutoff_sq = 4.0;
            std::uint32_t hits_a[kernel_block + kernel_slack], hits_b[kernel_block + kernel_slack];
            double d_a[kernel_block + kernel_slack], d_b[kernel_block + kernel_slack];
            const std::uint32_t found_a = kernel.one(x.data(), y.data(), z.data(), count, ax, ay,
                                                     az, shift, cutoff_sq, hits_a, d_a);
            const std::uint32_t found_b = kernels.back().one(
                x.data(), y.data(), z.data(), count, ax, ay, az, shift, cutoff_sq, hits_b, d_b);
            ASSERT_EQ(found_a, found_b) << "trial " << trial;
            std::uint32_t expected = 0;
            for (std::uint32_t k = 0; k < count; ++k) {
                // D = (x_b - x_a) + T, in that order
                const double dx = (x[k] - ax) + shift[0], dy = (y[k] - ay) + shift[1],
                             dz = (z[k] - az) + shift[2];
                expected += dx * dx + dy * dy + dz * dz < cutoff_sq ? 1u : 0u;
            }
            ASSERT_EQ(found_a, expected) << "trial " << trial;
            for (std::uint32_t h = 0; h < found_a; ++h) {
                ASSERT_EQ(hits_a[h], hits_b[h]);
                ASSERT_EQ(d_a[h], d_b[h]);
                ASSERT_LT(d_a[h], cutoff_sq);
            }
        }
    }
}

// within_images() of every kernel agrees bit for bit with the portable one and with
// D = (x_b - x_a) + T term for term, for every count (the vector groups and the masked tail),
// with an image at the cutoff up to rounding and one of length zero.
TEST(DistanceKernel, EveryImagesKernelMatchesThePortableOneBitForBit) {
    const auto kernels = distance_kernels();
    for (const auto& kernel : kernels) {
        SCOPED_TRACE(kernel.name);
        std::mt19937_64 rng(29);
        std::uniform_real_distribution<double> u(-3, 3);
        for (int trial = 0; trial < 2000; ++trial) {
            const std::uint32_t count = std::uint32_t(trial) % (kernel_block + 1);
            const double a[3] = {u(rng), u(rng), u(rng)}, b[3] = {u(rng), u(rng), u(rng)};
            const double d0[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
            std::vector<double> x(count), y(count), z(count);
            for (std::uint32_t k = 0; k < count; ++k) {
                x[k] = u(rng), y[k] = u(rng), z[k] = u(rng);
            }
            if (count > 3) {
                x[1] = 2.0 - d0[0], y[1] = -d0[1], z[1] = -d0[2]; // |D| = 2 up to rounding
                x[2] = -d0[0], y[2] = -d0[1], z[2] = -d0[2];      // D = 0
            }
            const double cutoff_sq = 4.0;
            std::uint32_t hits_a[kernel_block + kernel_slack], hits_b[kernel_block + kernel_slack];
            double d_a[kernel_block + kernel_slack], d_b[kernel_block + kernel_slack];
            const std::uint32_t found_a =
                kernel.images(x.data(), y.data(), z.data(), count, d0, cutoff_sq, hits_a, d_a);
            const std::uint32_t found_b = kernels.back().images(x.data(), y.data(), z.data(), count,
                                                                d0, cutoff_sq, hits_b, d_b);
            ASSERT_EQ(found_a, found_b) << "trial " << trial;
            std::uint32_t expected = 0;
            for (std::uint32_t k = 0; k < count; ++k) {
                const double dx = (b[0] - a[0]) + x[k], dy = (b[1] - a[1]) + y[k],
                             dz = (b[2] - a[2]) + z[k];
                const double d_sq = dx * dx + dy * dy + dz * dz;
                if (d_sq < cutoff_sq) {
                    ASSERT_LT(expected, found_a);
                    ASSERT_EQ(hits_a[expected], k);
                    ASSERT_EQ(d_a[expected], d_sq);
                    ++expected;
                }
            }
            ASSERT_EQ(found_a, expected) << "trial " << trial;
            for (std::uint32_t h = 0; h < found_a; ++h) {
                ASSERT_EQ(hits_a[h], hits_b[h]);
                ASSERT_EQ(d_a[h], d_b[h]);
            }
        }
    }
}

// square_roots() (AVX where the processor has it) is std::sqrt value for value, for every count
// (the vector groups and the tail) and for zeros, denormals, huge values and infinity.
TEST(DistanceKernel, SquareRootsMatchStdSqrtBitForBit) {
    std::mt19937_64 rng(23);
    std::uniform_real_distribution<double> u(0, 40);
    const double special[] = {0.0, 4.9e-324, 2.2e-308, 1e-300, 1.0, 2.0, 1e300, 1.7e308, HUGE_VAL};
    for (std::uint32_t count = 0; count <= kernel_block + 3; ++count) {
        std::vector<double> in(count), out(count, -1.0);
        for (std::uint32_t k = 0; k < count; ++k) {
            in[k] = k % 5 == 0 ? special[(k / 5) % std::size(special)] : u(rng);
        }
        tricell::detail::square_roots(in.data(), count, out.data());
        for (std::uint32_t k = 0; k < count; ++k) {
            ASSERT_EQ(out[k], std::sqrt(in[k])) << "count " << count << " value " << in[k];
        }
    }
}

// Every group kernel (several points against one range) gives, point by point and in order,
// what the portable one-point kernel gives, labelled g * kernel_block + k, for every group size
// and range length.
TEST(DistanceKernel, GroupKernelsMatchOnePointCallsInOrder) {
    using tricell::detail::kernel_group;
    const auto kernels = distance_kernels();
    for (const auto& kernel : kernels) {
        SCOPED_TRACE(kernel.name);
        std::mt19937_64 rng(29);
        std::uniform_real_distribution<double> u(-3, 3);
        for (int trial = 0; trial < 1500; ++trial) {
            SCOPED_TRACE(trial);
            const std::uint32_t count = std::uint32_t(trial) % (kernel_block + 1);
            const std::uint32_t group = 1 + std::uint32_t(trial / 7) % kernel_group;
            std::vector<double> x(count), y(count), z(count), ax(group), ay(group), az(group);
            for (std::uint32_t k = 0; k < count; ++k) {
                x[k] = u(rng), y[k] = u(rng), z[k] = u(rng);
            }
            for (std::uint32_t g = 0; g < group; ++g) {
                ax[g] = u(rng) / 2, ay[g] = u(rng) / 2, az[g] = u(rng) / 2;
            }
            // A zero shift on every third trial (the kernels skip adding it).
            const bool zero = trial % 3 == 0;
            const double shift[3] = {zero ? 0.0 : u(rng), zero ? -0.0 : u(rng),
                                     zero ? 0.0 : u(rng)};
            std::vector<std::uint32_t> expected_hits;
            std::vector<double> expected_d;
            for (std::uint32_t g = 0; g < group; ++g) {
                std::uint32_t hits[kernel_block + kernel_slack];
                double d[kernel_block + kernel_slack];
                const std::uint32_t found = kernels.back().one(
                    x.data(), y.data(), z.data(), count, ax[g], ay[g], az[g], shift, 4.0, hits, d);
                for (std::uint32_t h = 0; h < found; ++h) {
                    expected_hits.push_back(g * kernel_block + hits[h]);
                    expected_d.push_back(d[h]);
                }
            }
            std::vector<std::uint32_t> hits(group * count + kernel_slack);
            std::vector<double> d(group * count + kernel_slack);
            const std::uint32_t found =
                kernel.group(x.data(), y.data(), z.data(), count, ax.data(), ay.data(), az.data(),
                             group, shift, 4.0, hits.data(), d.data());
            ASSERT_EQ(found, expected_hits.size());
            for (std::uint32_t h = 0; h < found; ++h) {
                ASSERT_EQ(hits[h], expected_hits[h]);
                ASSERT_EQ(d[h], expected_d[h]);
            }
        }
    }
}
