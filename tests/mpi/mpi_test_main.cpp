// The main() of every MPI test program: one gtest report (rank 0 prints; the other ranks' printers
// are removed), every rank's verdict collected, and the line the test's regular expressions read
// ("MPI TESTS PASSED|FAILED on K ranks").
#include <cstdio>

#include <gtest/gtest.h>
#include <mpi.h>

#include "mpi_support.hpp"

int main(int argc, char** argv) {
    using tricell::testing::world_rank;
    using tricell::testing::world_size;
    MPI_Init(&argc, &argv);
    ::testing::InitGoogleTest(&argc, argv);
    if (world_rank() != 0) {
        delete ::testing::UnitTest::GetInstance()->listeners().Release(
            ::testing::UnitTest::GetInstance()->listeners().default_result_printer());
    }
    int failed = RUN_ALL_TESTS() != 0;
    int any = 0;
    MPI_Allreduce(&failed, &any, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
    if (world_rank() == 0) {
        std::printf("%s on %d ranks\n", any ? "MPI TESTS FAILED" : "MPI TESTS PASSED",
                    world_size());
    }
    MPI_Finalize();
    return any;
}
