#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "tricell/detail/distance_kernel.hpp"

using tricell::detail::kernel_block;

// The run-time selected kernel (AVX2 on most machines) must agree bit for bit with the portable
// one, for every block length including the scalar tail.
TEST(DistanceKernel, SelectedKernelMatchesPortableKernelBitForBit) {
    std::mt19937_64 rng(17);
    std::uniform_real_distribution<double> u(-3, 3);
    SCOPED_TRACE(tricell::detail::distance_kernel_name());
    for (int trial = 0; trial < 2000; ++trial) {
        const std::uint32_t count = std::uint32_t(trial) % (kernel_block + 1);
        std::vector<double> x(count), y(count), z(count);
        for (std::uint32_t k = 0; k < count; ++k) {
            x[k] = u(rng), y[k] = u(rng), z[k] = u(rng);
        }
        if (count > 3) {
            x[1] = 2.0, y[1] = 0.0, z[1] = 0.0; // exactly at the cutoff: not a hit
        }
        const double cutoff_sq = 4.0;
        std::uint32_t hits_a[kernel_block + 4], hits_b[kernel_block + 4];
        double d_a[kernel_block + 4], d_b[kernel_block + 4];
        const std::uint32_t found_a = tricell::detail::within_cutoff(
            x.data(), y.data(), z.data(), count, 0, 0, 0, cutoff_sq, hits_a, d_a);
        const std::uint32_t found_b = tricell::detail::within_cutoff_portable(
            x.data(), y.data(), z.data(), count, 0, 0, 0, cutoff_sq, hits_b, d_b);
        ASSERT_EQ(found_a, found_b) << "trial " << trial;
        std::uint32_t expected = 0;
        for (std::uint32_t k = 0; k < count; ++k) {
            expected += x[k] * x[k] + y[k] * y[k] + z[k] * z[k] < cutoff_sq ? 1u : 0u;
        }
        ASSERT_EQ(found_a, expected);
        for (std::uint32_t h = 0; h < found_a; ++h) {
            ASSERT_EQ(hits_a[h], hits_b[h]);
            ASSERT_EQ(d_a[h], d_b[h]);
            ASSERT_LT(d_a[h], cutoff_sq);
        }
    }
}
