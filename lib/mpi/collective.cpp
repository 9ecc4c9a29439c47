#include "collective.hpp"

#include <vector>

#include "tricell/error.hpp"

namespace tricell::mpi::detail {

void check_mpi(int code, const char* call) {
    if (code != MPI_SUCCESS) {
        char text[MPI_MAX_ERROR_STRING];
        int length = 0;
        MPI_Error_string(code, text, &length);
        tricell::detail::fail<Error>(call, " failed: ", std::string(text, std::size_t(length)));
    }
}

void agree(MPI_Comm comm, const std::string& error, int* min_value) {
    int rank = 0, size = 1;
    MPI_Comm_rank(comm, &rank);
    MPI_Comm_size(comm, &size);
    int values[2] = {error.empty() ? size : rank, min_value ? *min_value : 0};
    check_mpi(MPI_Allreduce(MPI_IN_PLACE, values, 2, MPI_INT, MPI_MIN, comm), "MPI_Allreduce");
    const int first = values[0];
    if (min_value) {
        *min_value = values[1];
    }
    if (first == size) {
        return;
    }
    int length = rank == first ? int(error.size()) : 0;
    check_mpi(MPI_Bcast(&length, 1, MPI_INT, first, comm), "MPI_Bcast");
    std::vector<char> text(std::size_t(length) + 1, '\0');
    if (rank == first) {
        error.copy(text.data(), error.size());
    }
    check_mpi(MPI_Bcast(text.data(), length, MPI_CHAR, first, comm), "MPI_Bcast");
    tricell::detail::fail<InvalidArgument>("rank ", first, ": ", text.data());
}

} // namespace tricell::mpi::detail
