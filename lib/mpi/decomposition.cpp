#include "tricell/mpi/decomposition.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include "collective.hpp"
#include "tricell/error.hpp"

namespace tricell::mpi {

using tricell::detail::fail;

Decomposition::Decomposition(MPI_Comm comm, std::array<int, 3> dims) {
    detail::check_mpi(MPI_Comm_dup(comm, &comm_), "MPI_Comm_dup");
    MPI_Comm_rank(comm_, &rank_);
    MPI_Comm_size(comm_, &size_);
    std::string error;
    for (int axis = 0; axis < 3; ++axis) {
        if (dims[std::size_t(axis)] < 0) {
            error = tricell::detail::cat("dims[", axis, "] must be >= 0 (got ",
                                         dims[std::size_t(axis)], ")");
        }
    }
    if (error.empty()) {
        // MPI_Dims_create fills the zero entries; it fails when the fixed ones do not divide.
        const long fixed = long(std::max(dims[0], 1)) * std::max(dims[1], 1) * std::max(dims[2], 1);
        const bool free_entries = dims[0] == 0 || dims[1] == 0 || dims[2] == 0;
        if ((free_entries && size_ % fixed != 0) || (!free_entries && fixed != size_)) {
            error = tricell::detail::cat("dims ", dims[0], " x ", dims[1], " x ", dims[2],
                                         " do not fit ", size_, " ranks");
        } else if (free_entries) {
            detail::check_mpi(MPI_Dims_create(size_, 3, dims.data()), "MPI_Dims_create");
        }
    }
    if (!error.empty()) {
        MPI_Comm_free(&comm_);
        comm_ = MPI_COMM_NULL;
        fail<InvalidArgument>(error);
    }
    dims_ = dims;
    reset_bounds();
}

namespace {
// Frees a communicator the decomposition holds (not after MPI_Finalize).
void release(MPI_Comm& comm) {
    if (comm != MPI_COMM_NULL) {
        int finalized = 0;
        MPI_Finalized(&finalized);
        if (!finalized) {
            MPI_Comm_free(&comm);
        }
        comm = MPI_COMM_NULL;
    }
}
} // namespace

Decomposition::~Decomposition() {
    release(comm_);
}

Decomposition::Decomposition(Decomposition&& other) noexcept
    : comm_(std::exchange(other.comm_, MPI_COMM_NULL)), rank_(other.rank_), size_(other.size_),
      dims_(other.dims_), bounds_(std::move(other.bounds_)) {}

Decomposition& Decomposition::operator=(Decomposition&& other) noexcept {
    if (this != &other) {
        // Not this->~Decomposition(): that would end the lifetime of bounds_ before the
        // assignment below writes into it.
        release(comm_);
        comm_ = std::exchange(other.comm_, MPI_COMM_NULL);
        rank_ = other.rank_;
        size_ = other.size_;
        dims_ = other.dims_;
        bounds_ = std::move(other.bounds_);
    }
    return *this;
}

std::array<int, 3> Decomposition::coords(int rank) const {
    return {{rank / (dims_[1] * dims_[2]), (rank / dims_[2]) % dims_[1], rank % dims_[2]}};
}

int Decomposition::rank_at(const std::array<int, 3>& c) const {
    return (c[0] * dims_[1] + c[1]) * dims_[2] + c[2];
}

void Decomposition::set_bounds(int axis, std::vector<double> bounds) {
    if (axis < 0 || axis > 2) {
        fail<InvalidArgument>("axis must be 0, 1 or 2 (got ", axis, ")");
    }
    const int n = dims_[std::size_t(axis)];
    if (bounds.size() != std::size_t(n) + 1) {
        fail<InvalidArgument>("axis ", axis, " needs ", n + 1, " bounds (got ", bounds.size(), ")");
    }
    if (bounds.front() != 0 || bounds.back() != 1) {
        fail<InvalidArgument>("bounds of axis ", axis, " must start at 0 and end at 1 (got ",
                              bounds.front(), " ... ", bounds.back(), ")");
    }
    for (std::size_t k = 1; k < bounds.size(); ++k) {
        if (!std::isfinite(bounds[k]) || !(bounds[k] > bounds[k - 1])) {
            fail<InvalidArgument>("bounds of axis ", axis, " must increase strictly (bound ", k,
                                  " is ", bounds[k], " after ", bounds[k - 1], ")");
        }
    }
    bounds_[std::size_t(axis)] = std::move(bounds);
}

void Decomposition::reset_bounds() {
    for (std::size_t axis = 0; axis < 3; ++axis) {
        const int n = dims_[axis];
        bounds_[axis].resize(std::size_t(n) + 1);
        for (int k = 0; k <= n; ++k) {
            bounds_[axis][std::size_t(k)] = double(k) / n;
        }
    }
}

int Decomposition::interval(int axis, double s) const {
    const std::vector<double>& b = bounds_[std::size_t(axis)];
    // The last boundary <= s, clamped to the intervals that exist.
    const auto it = std::upper_bound(b.begin() + 1, b.end() - 1, s);
    return int(it - b.begin()) - 1;
}

int Decomposition::owner(const Fractional& wrapped) const {
    return rank_at({{interval(0, wrapped[0]), interval(1, wrapped[1]), interval(2, wrapped[2])}});
}

Fractional Decomposition::lower(int rank) const {
    const std::array<int, 3> c = coords(rank);
    return Fractional(bounds_[0][std::size_t(c[0])], bounds_[1][std::size_t(c[1])],
                      bounds_[2][std::size_t(c[2])]);
}

Fractional Decomposition::upper(int rank) const {
    const std::array<int, 3> c = coords(rank);
    return Fractional(bounds_[0][std::size_t(c[0]) + 1], bounds_[1][std::size_t(c[1]) + 1],
                      bounds_[2][std::size_t(c[2]) + 1]);
}

} // namespace tricell::mpi
