// Domain boundaries placed by estimated work: equal volume, equal atoms, or the occupancy-moment
// model of design note 001.
//
// The work model. Bin all atoms (over all ranks) into a grid of cells of about the cutoff per
// axis (perpendicular widths, as the serial search does). A cell-list search with cells of side
// h ~ r_c tests, for a cell holding n atoms, about n * (sum of the occupancies of its
// stencil_cells(1) = 27 stencil cells) / 2 pairs. Where the density varies on scales larger than a
// cell (a liquid slab in a gas) the neighbours hold about as many atoms as the cell itself, so
// a cell costs about per_atom * n + per_test * (27 / 2) * n^2, and a set of M cells (a slab)
//     W = M * (per_atom * E[n] + per_test * (27 / 2) * E[n^2]),
// with E[n], E[n^2] the first and second moments of its cell occupancies. The second moment is
// what equal-atom balancing misses: pairs grow with the square of the local density, and the
// variance of n (clustering) adds to E[n^2] = Var(n) + E[n]^2. per_atom (integration, binning,
// bookkeeping per atom) is measured in units of one distance test; the default 10 is a guess, not
// a fit. This is the only place the formula lives (cell_work() below).
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
#include "tricell/types.hpp"

namespace tricell::mpi {

enum class BalanceRule { equal_volume, equal_atoms, moments };

struct TRICELL_MPI_API WorkModel {
    double per_atom = 10; ///< cost of an atom, in distance tests
    double per_test = 1;  ///< cost of a distance test
    /// Cap on the cells of the occupancy grid (the cells grow when it bites).
    std::size_t max_cells = std::size_t(1) << 21;
    /// Throws InvalidArgument naming the field and value.
    void validate() const;
};

/// The moment model: work of `cells` cells whose occupancies have mean `mean_n` and mean square
/// `mean_n_sq` (the formula above).
TRICELL_MPI_API double cell_work(const WorkModel& model, double cells, double mean_n,
                                 double mean_n_sq);

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
