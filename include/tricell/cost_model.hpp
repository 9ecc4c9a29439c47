// Cost models: the formulas that choose how a search runs. Code that decides calls them;
// benchmarks (benchmarks/verlet_bench.cpp, benchmarks/backend_bench.cpp) measure the constants.
//
// Work of a region from the moments of its cell occupancy. A cell holding n atoms, paired with K
// stencil cells of similar occupancy, costs about n * K * n distance tests, plus a fixed cost per
// visit of a non-empty cell and a cost per atom. Summed over a region of C cells,
//     W = c_visit K C_nonempty + c_atom sum(n) + c_test K sum(n^2)
//       = C (c_visit K P[n > 0] + c_atom E[n] + c_test K E[n^2]),
// so the work grows with the second moment E[n^2]: with density, squared, not with the atom count
// (pairs grow as rho^2). Threads (NeighborSearch::compute) split the work units into contiguous
// chunks of equal W, and the MPI decomposition places domain boundaries the same way.
//
// Dense grid or compact hash. The dense grid stores every cell (cheapest per candidate: a stencil
// row is one contiguous range) but at most max_cells = 4 N + 64 of them, so memory follows the
// atoms. The cell count the cutoff asks for is C_full = prod(max(1, floor(w_a / h))) over the
// region the atoms span. When C_full fits under the cap, the dense grid runs at full resolution
// and wins. When it does not (a droplet in a large box, vacuum, clusters far apart), the dense
// grid must grow its cells by a factor g = (C_full / cap)^(1/3) per axis and the candidates per
// atom grow by g^3 wherever the atoms are, while the hash keeps full resolution and pays only a
// lookup per (non-empty cell, stencil cell). With tests per atom t = K rho h^3 at full resolution
// and lookups costing c_lookup distance tests each, the hash wins when
//     c_test t g^3  >  c_test t + c_lookup K / max(1, rho h^3),
// which for any real clustering (g^3 >= 2) holds by a wide margin; choose_grid_backend() takes
// the hash as soon as the cap would bite (C_full > cap).
#pragma once

#include <cstddef>
#include <vector>

#include "tricell/export.hpp"
#include "tricell/neighbor_list.hpp"

namespace tricell {

/// Constants of the occupancy work model, in units of one distance test (measured by
/// benchmarks/backend_bench.cpp on the reference machine).
struct OccupancyCosts {
    double per_visit = 4; ///< c_visit: per (non-empty cell, stencil cell) visited
    double per_atom = 8;  ///< c_atom: per atom of a cell
    double per_test = 1;  ///< c_test: per distance test
};

/// W of one unit holding `atoms` atoms paired with `neighbours` stencil units (see above).
TRICELL_API double occupancy_work(double atoms, double neighbours,
                                  const OccupancyCosts& costs = OccupancyCosts());

/// Moments of a set of cell occupancies: count, sum(n), sum(n^2), non-empty cells.
struct OccupancyMoments {
    double cells = 0;
    double atoms = 0;
    double atoms_sq = 0;
    double nonempty = 0;
    void add(double n) {
        cells += 1;
        atoms += n;
        atoms_sq += n * n;
        nonempty += n > 0 ? 1 : 0;
    }
    double mean() const { return cells > 0 ? atoms / cells : 0; }       ///< E[n]
    double mean_sq() const { return cells > 0 ? atoms_sq / cells : 0; } ///< E[n^2]
};

/// W of a region from its moments: c_visit K C_nonempty + c_atom sum(n) + c_test K sum(n^2).
TRICELL_API double region_work(const OccupancyMoments& moments, double neighbours,
                               const OccupancyCosts& costs = OccupancyCosts());

/// Expected pairs (full list) of the atoms of one cell of `atoms` atoms and real volume
/// `volume`, for a search sphere of volume `sphere`: atoms * (atoms / volume) * sphere, the local
/// density carried over the sphere. Summed over cells this is sphere * sum(n^2 / V_cell), the
/// second moment again; it sizes the pair arrays before a search (an overestimate only reserves
/// address space that is never touched).
TRICELL_API double expected_pairs(double atoms, double volume, double sphere);

/// Splits units 0..W.size()-1 into at most `parts` contiguous chunks of about equal total work.
/// Returns the chunk boundaries: bounds[0] = 0, bounds.back() = W.size().
TRICELL_API std::vector<std::size_t> split_work(const std::vector<double>& work, std::size_t parts);

/// Dense or hash for a grid search: dense when the full-resolution cell count fits the cap.
TRICELL_API SearchBackend choose_grid_backend(double full_resolution_cells, double max_cells);

/// How the cell size h of a build relates to the radii (cells_per_cutoff = r_l / h).
enum class CellSize {
    list_radius,       ///< h = r_l: one cell per list radius, 27-cell stencil
    cutoff,            ///< h = r_c: cells of the cutoff, the stencil reaching two cells
    half_list_radius,  ///< h = r_l / 2 (the default cells_per_cutoff = 2)
    third_list_radius, ///< h = r_l / 3
};

/// cells_per_cutoff (cells per list radius) for a rule: r_l / h.
TRICELL_API double cells_per_list_radius(CellSize rule, double cutoff, double skin);

/// Stencil entries of the idealised grid: cubic cells of side h = r / k, offsets a in Z^3 whose
/// cells come closer than r, i.e. sum over axes of max(0, |a| - 1)^2 < k^2 (27 for k = 1, 125
/// for k = 2). A build tests about density * stencil_cells(k) * h^3 pairs per atom.
TRICELL_API std::size_t stencil_cells(double cells_per_cutoff);

/// Inputs of the skin cost model, all per atom: costs in any one time unit (measured, e.g. by
/// benchmarks/verlet_bench.cpp), lengths in the units of the box. With g = 1/2 for half lists
/// (else 1), r_l = r_c + skin, h = r_l / k and n(k) = stencil_cells(k):
///     candidates       n_c = g rho (4 pi / 3) r_l^3
///     build tests      n_t = g rho n(k) h^3
///     cell visits      n_v = g n(k) / (rho h^3)
///     C_b = build_per_atom + build_per_test n_t + build_per_cell_visit n_v
///     C_f = refresh_per_atom + refresh_per_candidate n_c
///     steps per build  L = 1 + skin / (2 v)
///     cost per step    C = C_b / L + C_f
/// The cost of the force loop itself (pairs within r_c) does not depend on the skin and is left
/// out.
struct TRICELL_API SkinCostModel {
    double cutoff = 0;                ///< r_c
    double density = 0;               ///< rho, atoms per unit volume
    double displacement_per_step = 0; ///< v: largest atom displacement per step
    bool half = true;
    double build_per_atom = 0;        ///< part of a build independent of the radius
    double build_per_test = 0;        ///< per distance test during a build
    double build_per_cell_visit = 0;  ///< per (cell, stencil entry) visited during a build
    double refresh_per_atom = 0;      ///< per step: the displacement check
    double refresh_per_candidate = 0; ///< per step: filtering one candidate
    double max_skin = 0;              ///< largest skin considered; 0 means r_c

    /// Throws InvalidArgument naming the offending field and value.
    void validate() const;
};

/// The model's prediction for one skin and cell size.
struct SkinPrediction {
    double skin = 0;
    CellSize cell_size = CellSize::half_list_radius;
    double cells_per_cutoff = 2;     ///< r_l / h, to put into VerletOptions
    double steps_per_build = 1;      ///< L
    double candidates_per_atom = 0;  ///< n_c
    double build_tests_per_atom = 0; ///< n_t
    double build_cost = 0;           ///< C_b per atom
    double refresh_cost = 0;         ///< C_f per atom
    double cost_per_step = 0;        ///< C per atom
};

/// The model evaluated at one skin and cell-size rule.
TRICELL_API SkinPrediction predict_skin_cost(const SkinCostModel& model, double skin,
                                             CellSize cell_size);
/// The skin in [0, max_skin] minimising the cost per step for one cell-size rule.
TRICELL_API SkinPrediction tune_skin(const SkinCostModel& model, CellSize cell_size);
/// The skin and cell-size rule minimising the cost per step.
TRICELL_API SkinPrediction tune_skin(const SkinCostModel& model);

} // namespace tricell
