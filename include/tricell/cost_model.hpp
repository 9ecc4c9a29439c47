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
//
// Direct image enumeration for tiny cells. When a cell is narrower than the cutoff, a grid has one
// cell per axis and a stencil of hundreds of offsets, each its own image, and every (image, atom)
// becomes a separate range of N atoms: the grid pays its per-range overhead and the stencil's
// construction hundreds of times for a few pairs. The direct backend tests all N^2 pairs through
// every image that can hold one, each pair only through the images its own distance allows.
// Counted with callgrind (instructions per call, issue 13, after that per-pair pruning): 1 and
// 2 atoms at rc 8-10, about 10x fewer than the dense grid; 8 atoms at rc 10 (cutoff 1.8 widths),
// 1.5x fewer; 32 atoms at rc 8 (1.2 widths), 1.4x fewer; but 16 atoms at rc 6 (0.95 widths)
// 1.15x more, 48 atoms at rc 7 (0.8 widths) 1.4x more, 64 atoms at rc 10 (0.9 widths) 1.5x
// more. choose_direct() takes it for at most 12 atoms when the cutoff reaches past half the
// narrowest periodic width (or nothing is periodic), and for at most 32 atoms when it reaches
// past the whole width, where N^2 x images stays below the grid's range scans.
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

/// Direct enumeration (see above) for `atoms` atoms, narrowest periodic width `min_width`
/// (infinity when no axis is periodic) and search radius `radius`.
TRICELL_API bool choose_direct(std::size_t atoms, double min_width, double radius);

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

// ---- Uniform grid or octree: the two-density model (design note 001) -------------------------
//
// A system of volume V holds a volume fraction f at density rho_hi and the rest at rho_lo (a
// droplet or a liquid slab in its vapour, a cluster in vacuum). Both structures cost about the
// same per atom wherever the density is the same, so each is described by its cost per atom u(rho)
// at a uniform density, and the whole search costs
//     T = V [ f rho_hi u(rho_hi) + (1 - f) rho_lo u(rho_lo) ].
// Uniform grid (cells of side h = r / k, K stencil cells; occupancy lambda = rho h^3): building is
// a pass per atom, searching visits K cells per non-empty cell (a fraction 1 - e^-lambda of the
// cells are non-empty, so per atom (1 - e^-lambda) / lambda of them) and tests K lambda atoms:
//     u_grid(rho) = g_0 + g_visit K (1 - e^-lambda) / lambda + g_test K lambda.
// The dense grid and the hash have their own constants (the hash pays a lookup per visit); the
// grid is the one choose_grid_backend() picks. Octree (leaves of about n atoms, side
// l = (n / rho)^(1/3)): an atom is tested against the leaves whose boxes come within r of its
// leaf, about the atoms of a cube of side 2 l dilated by r (Minkowski: cube plus slabs, quarter
// cylinders and a ball), so with x = rho r^3 the tests per atom and the leaf pairs per atom are
//     t(rho) = 8 n + 24 n^(2/3) x^(1/3) + 6 pi n^(1/3) x^(2/3) + (4 pi / 3) x,   t / n,
// and building splits each atom through about log8(N / n) levels (folded into o_0):
//     u_oct(rho) = o_0 + (o_test + o_leaf / n) t(rho) = o_0 + o_1 t(rho).
// The octree adapts its cells to the density, the grid does not: at low density the grid pays
// K visits per atom for nearly empty cells (u_grid > u_oct), at high density its contiguous rows
// beat the tree's walk (u_grid < u_oct). Setting T_grid = T_oct gives the crossover
//     f* = rho_lo D_lo / (rho_lo D_lo + rho_hi D_hi),
//     D_lo = u_grid(rho_lo) - u_oct(rho_lo),   D_hi = u_oct(rho_hi) - u_grid(rho_hi),
// and the octree is the cheaper for f < f* (f* = 0 when the octree loses at both densities, 1 when
// it wins at both). f* is small whenever rho_lo << rho_hi: the dense phase must be a small part
// of the volume before the vapour's savings outweigh its extra cost. automatic_backend() (in
// lib/neighbor_list.cpp) evaluates T in its general form, the sum of u(rho_i) over the atoms,
// with each atom's local density rho_i read from a sample of at most 4096 atoms binned in cells
// of at least 2 r, and takes the octree when T_oct < 0.7 T_grid (a clear win: those cells read a
// cluster's surface as vapour, and the fitted costs scatter by about 20%); it skips the sample
// when grid_always_cheaper() (the dense grid, on the reference machine). The constants below were
// fitted by benchmarks/backend_bench.cpp (`uniform`) on the reference machine (one core), in
// nanoseconds per atom, and checked there (`mixture`) against the measured crossover of two-density
// systems.

/// Constants of the grid-vs-octree model, ns per atom (see above; fitted by backend_bench).
struct OctreeCosts {
    double dense[3] = {539.9, -9.92, 0.8556}; ///< g_0, g_visit, g_test of the dense grid
    double hash[3] = {785.6, 8.903, 0.3395};  ///< g_0, g_visit, g_test of the compact hash
    double octree[2] = {253.4, 1.873};        ///< o_0, o_1
    double leaf_occupancy = 11;               ///< n: mean atoms per leaf at leaf_size
    double leaf_size = 16;                    ///< n_max when NeighborOptions::leaf_size is 0
};

/// The octree's n_max when NeighborOptions::leaf_size is 0.
TRICELL_API std::size_t octree_leaf_size(const OctreeCosts& costs = OctreeCosts());

/// u_grid(rho) of the dense grid or the hash (`grid`), cubic cells of side cutoff.
TRICELL_API double grid_cost_per_atom(SearchBackend grid, double density, double cutoff,
                                      const OctreeCosts& costs = OctreeCosts());
/// u_oct(rho).
TRICELL_API double octree_cost_per_atom(double density, double cutoff,
                                        const OctreeCosts& costs = OctreeCosts());
/// True when u_grid < u_oct at every density rho with rho r^3 from 1e-6 to 16 (r = `cutoff`;
/// the range the constants were fitted over)
/// (then no mixture of densities can favour the octree and auto need not look at the atoms).
TRICELL_API bool grid_always_cheaper(SearchBackend grid, double cutoff,
                                     const OctreeCosts& costs = OctreeCosts());
/// f*: below this volume fraction of the dense phase the octree is the cheaper (see above).
TRICELL_API double octree_crossover(SearchBackend grid, double rho_hi, double rho_lo, double cutoff,
                                    const OctreeCosts& costs = OctreeCosts());

} // namespace tricell
