// Helpers for collectives that must fail together: a rank that finds bad input must not throw
// alone (the others would wait forever in the next collective), so every check is followed by
// agree(), which makes every rank throw the first failing rank's message.
#pragma once

#include <exception>
#include <string>

#include <mpi.h>

namespace tricell::mpi::detail {

/// Collective. `error` is this rank's message, empty when it is fine. If any rank failed, every
/// rank throws InvalidArgument("rank R: message") for the lowest failing rank R. With
/// `min_value`, the same single MPI_Allreduce also replaces *min_value by its minimum over ranks.
void agree(MPI_Comm comm, const std::string& error, int* min_value = nullptr);

/// Collective. Runs check(), catching what it throws, then agree()s (with min_value as there:
/// a vote taken by the same MPI_Allreduce).
template <class Check> void agreed(MPI_Comm comm, Check&& check, int* min_value = nullptr) {
    std::string error;
    try {
        check();
    } catch (const std::exception& e) {
        error = e.what();
        if (error.empty()) {
            error = "unknown error";
        }
    }
    agree(comm, error, min_value);
}

/// Throws tricell::Error naming the MPI call when an MPI function did not return MPI_SUCCESS.
void check_mpi(int code, const char* call);

} // namespace tricell::mpi::detail
