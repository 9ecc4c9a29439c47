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

void agree(MPI_Comm comm, const std::string& error) {
    int rank = 0, size = 1;
    MPI_Comm_rank(comm, &rank);
    MPI_Comm_size(comm, &size);
    const int mine = error.empty() ? size : rank;
    int first = size;
    check_mpi(MPI_Allreduce(&mine, &first, 1, MPI_INT, MPI_MIN, comm), "MPI_Allreduce");
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
