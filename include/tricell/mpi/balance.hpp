// Domain boundaries placed by estimated work: equal volume, equal atoms, or the occupancy-moment
// model of the serial search's cost model.
//
// The work model is the serial search's occupancy-moment estimate (region_work of the library's
// cost model):
// bin all atoms (over all ranks) into a grid of cells of about the cutoff per axis (perpendicular
// widths, as the serial search does); a set of C cells (a slab, a domain) paired with
// K = stencil_cells(1) = 27 stencil cells costs
//     W = C (c_visit K P[n > 0] + c_atom E[n] + c_test K E[n^2]),
// with E[n], E[n^2] the first and second moments of its cell occupancies. The second moment is
// what equal-atom balancing misses: pairs grow with the square of the local density, and
// clustering adds its variance, E[n^2] = Var(n) + E[n]^2. The constants are
// tricell::OccupancyCosts (measured by benchmarks/backend_bench.cpp); nothing here restates the
// formula.
//
// Boundaries. The decomposition is a tensor grid, so each axis is balanced on its own: the
// per-slab work along that axis (slab k = all cells with index k on the axis) is accumulated
// and the dims - 1 inner boundaries are put where the cumulative work reaches 1/dims, 2/dims,
// ... of the total, interpolating linearly inside a slab (boundaries at least 1e-6 apart).
// Equal atoms is the same with W = number of atoms; equal volume resets to uniform boundaries.
// balance() is collective (one MPI_Allreduce of the cell counts); call it when the density has
// changed, then migrate().
#pragma once

#include <cstddef>
#include <vector>

#include "tricell/box.hpp"
#include "tricell/mpi/decomposition.hpp"
#include "tricell/mpi/export.hpp"
#include "tricell/tuning.hpp"
#include "tricell/types.hpp"

namespace tricell::mpi {

enum class BalanceRule { equal_volume, equal_atoms, moments };

struct TRICELL_MPI_API WorkModel {
    /// c_visit, c_atom, c_test of tricell::region_work.
    OccupancyCosts costs;
    /// Cap on the cells of the occupancy grid (the cells grow when it bites).
    std::size_t max_cells = std::size_t(1) << 21;
    /// Throws InvalidArgument naming the field and value.
    void validate() const;
};

/// Collective: sets the boundaries of every axis of the decomposition by the rule, from the
/// positions of the atoms every rank holds (owned or not; each atom on exactly one rank).
TRICELL_MPI_API void balance(Decomposition& decomposition, const Box& box, PointsView positions,
                             double cutoff, BalanceRule rule, const WorkModel& model = {});

/// Collective: the moment model's work of every rank's domain for the current boundaries
/// (cells cut by a boundary shared by volume), the same vector on every rank.
TRICELL_MPI_API std::vector<double> estimate_rank_work(const Decomposition& decomposition,
                                                       const Box& box, PointsView positions,
                                                       double cutoff, const WorkModel& model = {});

} // namespace tricell::mpi
