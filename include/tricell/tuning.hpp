// What a user tunes about how a search runs: the Verlet skin (and the cell size that goes with
// it), from a cost model of a build and of a refresh per step, and the constants of the
// occupancy work model that the MPI load balance takes.
//
// The skin model. With g = 1/2 for half lists (else 1), r_l = r_c + skin, h = r_l / k and
// n(k) = stencil_cells(k), per atom (a build walks the half stencil for either list, a full one
// turning each pair it finds around):
//     candidates       n_c = g rho (4 pi / 3) r_l^3
//     build tests      n_t = rho n(k) h^3 / 2
//     cell visits      n_v = n(k) / (2 rho h^3)
//     C_b = build_per_atom + build_per_test n_t + build_per_cell_visit n_v
//     C_f = refresh_per_atom + refresh_per_candidate n_c
//     steps per build  L = 1 + skin / (2 v)
//     cost per step    C = C_b / L + C_f
// A larger skin rebuilds less often but filters more candidates every step; tune_skin() finds
// the minimum of C over the skin and the cell-size rule. The force loop itself (pairs within
// r_c) does not depend on the skin and is left out. benchmarks/verlet_bench.cpp measures the
// constants on a machine.
#pragma once

#include <cstddef>

#include "tricell/export.hpp"

namespace tricell {

/// Constants of the occupancy work model (the library's private cost model), in units of one
/// distance test; benchmarks/backend_bench.cpp measures them.
struct OccupancyCosts {
    double per_visit = 4; ///< c_visit: per (non-empty cell, stencil cell) visited
    double per_atom = 8;  ///< c_atom: per atom of a cell
    double per_test = 1;  ///< c_test: per distance test
};

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

/// Inputs of the skin cost model (see above), all per atom: costs in any one time unit,
/// lengths in the units of the box.
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
