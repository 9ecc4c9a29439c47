// A grid of domains over the box's fractional space, one domain per MPI rank.
//
// The unit cube of fractional coordinates is cut along each axis alpha at dims[alpha] + 1
// boundaries 0 = b_0 < b_1 < ... < b_dims = 1, and the rank at grid coordinates (ka, kb, kc) (row
// major, c fastest: rank = (ka * dims_b + kb) * dims_c + kc) owns the product of the intervals
// [b_k, b_{k+1}). Domains are therefore parallelepipeds spanned by the lattice vectors, like
// LAMMPS's domains in lamda coordinates, and a box that deforms keeps its decomposition. An atom
// belongs to the domain containing its WRAPPED fractional position; along an open axis positions
// are not wrapped and may lie anywhere, so there the first domain reaches down to -infinity and
// the last up to +infinity. The boundaries start uniform and can be moved per axis
// (set_bounds, or tricell::mpi::balance from a work estimate); every rank must hold the same.
//
// The decomposition holds a duplicate of the caller's communicator, so tricell's messages never
// meet the caller's. It must be destroyed before MPI_Finalize.
#pragma once

#include <array>
#include <vector>

#include <mpi.h>

#include "tricell/mpi/export.hpp"
#include "tricell/types.hpp"

namespace tricell::mpi {

class TRICELL_MPI_API Decomposition {
  public:
    /// Collective over comm. Entries of dims that are 0 are chosen by MPI_Dims_create; the
    /// product of the result must be the size of comm (InvalidArgument otherwise, on every rank).
    explicit Decomposition(MPI_Comm comm, std::array<int, 3> dims = {0, 0, 0});
    ~Decomposition();
    Decomposition(const Decomposition&) = delete;
    Decomposition& operator=(const Decomposition&) = delete;
    Decomposition(Decomposition&& other) noexcept;
    Decomposition& operator=(Decomposition&& other) noexcept;

    /// The (duplicated) communicator all of tricell::mpi's collectives run on.
    MPI_Comm comm() const { return comm_; }
    int rank() const { return rank_; }
    int size() const { return size_; }
    const std::array<int, 3>& dims() const { return dims_; }

    /// Grid coordinates of a rank and back.
    std::array<int, 3> coords(int rank) const;
    int rank_at(const std::array<int, 3>& coords) const;

    /// The dims[axis] + 1 boundaries along an axis: 0, ..., 1, strictly increasing.
    const std::vector<double>& bounds(int axis) const { return bounds_[axis]; }
    /// Replaces the boundaries of one axis (not collective: give every rank the same). Throws
    /// InvalidArgument unless there are dims[axis] + 1 finite values, first 0, last 1, strictly
    /// increasing.
    void set_bounds(int axis, std::vector<double> bounds);
    /// Back to equal widths on every axis.
    void reset_bounds();

    /// The interval index along an axis of a fractional coordinate (values below 0 go to the
    /// first interval and values at or above 1 to the last, as on an open axis).
    int interval(int axis, double s) const;
    /// The rank owning a wrapped fractional position.
    int owner(const Fractional& wrapped) const;
    /// Lower and upper fractional bounds of a rank's domain (without the infinite extension of
    /// the end domains along open axes).
    Fractional lower(int rank) const;
    Fractional upper(int rank) const;

  private:
    MPI_Comm comm_ = MPI_COMM_NULL;
    int rank_ = 0;
    int size_ = 1;
    std::array<int, 3> dims_{{1, 1, 1}};
    std::array<std::vector<double>, 3> bounds_;
};

} // namespace tricell::mpi
