// The cost model: the formulas behind every choice of how a search runs (lib/policy/policy.cpp
// calls them and nothing else decides). benchmarks/backend_bench.cpp fits the constants; the
// skin model and the occupancy constants a user tunes are public (tricell/tuning.hpp). Private
// to the library: tests and benchmarks include it directly.
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
// Counted in instructions per call, it wins by up to 10x for one or two atoms and loses once
// the cell is about as wide as the cutoff with a few dozen atoms: choose_direct() takes it for
// at most 12 atoms when the cutoff reaches past half the narrowest periodic width (or nothing is
// periodic), and for at most 32 atoms when it reaches past the whole width, where
// N^2 x images stays below the grid's range scans (the counts are in benchmarks/README.md).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <numeric>
#include <vector>

#include "detail/pi.hpp"
#include "tricell/box.hpp"
#include "tricell/neighbor_list.hpp"
#include "tricell/tuning.hpp"

namespace tricell {

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

// ---- Uniform grid or octree: the two-density model ------------------------------------------
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
// lib/policy/policy.cpp) evaluates T in its general form, the sum of u(rho_i) over the atoms,
// with each atom's local density rho_i read from a sample of at most 4096 atoms binned in cells
// of at least 2 r, and takes the octree when T_oct < 0.7 T_grid (a clear win: those cells read a
// cluster's surface as vapour, and the fitted costs scatter by about 20%); it skips the sample
// when grid_always_cheaper(). The constants below are fitted by benchmarks/backend_bench.cpp
// (`uniform`) on one core, in nanoseconds per atom, and checked there (`mixture`) against the
// measured crossover of two-density systems.

/// Constants of the grid-vs-octree model, ns per atom (see above; fitted by backend_bench).
struct OctreeCosts {
    double dense[3] = {539.9, -9.92, 0.8556}; ///< g_0, g_visit, g_test of the dense grid
    double hash[3] = {785.6, 8.903, 0.3395};  ///< g_0, g_visit, g_test of the compact hash
    double octree[2] = {253.4, 1.873};        ///< o_0, o_1
    double leaf_occupancy = 11;               ///< n: mean atoms per leaf at leaf_size
    double leaf_size = 16;                    ///< n_max when NeighborOptions::leaf_size is 0
};

/// W of one unit holding `atoms` atoms paired with `neighbours` stencil units (see above).
inline double occupancy_work(double atoms, double neighbours,
                             const OccupancyCosts& costs = OccupancyCosts()) {
    if (atoms <= 0) {
        return 0;
    }
    return costs.per_visit * neighbours + costs.per_atom * atoms +
           costs.per_test * neighbours * atoms * atoms;
}

/// W of a region from its moments: c_visit K C_nonempty + c_atom sum(n) + c_test K sum(n^2).
inline double region_work(const OccupancyMoments& m, double neighbours,
                          const OccupancyCosts& costs = OccupancyCosts()) {
    return costs.per_visit * neighbours * m.nonempty + costs.per_atom * m.atoms +
           costs.per_test * neighbours * m.atoms_sq;
}

/// Expected pairs (full list) of the atoms of one cell of `atoms` atoms and real volume `volume`,
/// for a search sphere of volume `sphere`: atoms * (atoms / volume) * sphere, the local density
/// carried over the sphere. Summed over cells this is sphere * sum(n^2 / V_cell), the second
/// moment again; it sizes the pair arrays before a search and estimates a whole system's pairs.
inline double expected_pairs(double atoms, double volume, double sphere) {
    if (!(volume > 0) || !(atoms > 0)) {
        return 0;
    }
    return atoms * atoms / volume * sphere;
}

/// Splits units 0..W.size()-1 into at most `parts` contiguous chunks of about equal total work.
/// Returns the chunk boundaries: bounds[0] = 0, bounds.back() = W.size().
template <class Work> std::vector<std::size_t> split_work(const Work& work, std::size_t parts) {
    std::vector<std::size_t> bounds{0};
    const std::size_t units = work.size();
    const double total = std::accumulate(work.begin(), work.end(), 0.0);
    if (parts > 1 && total > 0) {
        double running = 0;
        for (std::size_t u = 0; u + 1 < units && bounds.size() < parts; ++u) {
            running += work[u];
            if (running >= total * double(bounds.size()) / double(parts)) {
                bounds.push_back(u + 1);
            }
        }
    }
    bounds.push_back(units);
    return bounds;
}

/// Direct enumeration (see above) for `atoms` atoms, narrowest periodic width `min_width`
/// (infinity when no axis is periodic) and search radius `radius`.
inline bool choose_direct(std::size_t atoms, double min_width, double radius) {
    if (!std::isfinite(min_width)) {
        return atoms <= 12;
    }
    return (atoms <= 12 && min_width < 2 * radius) || (atoms <= 32 && min_width < radius);
}

/// The most periodic images the direct backend enumerates (a few hundred MB of images): past
/// that it refuses the search, naming the radius, rather than allocate gigabytes.
constexpr double max_direct_images = double(1 << 22);

/// Cells per cutoff of a grid search (when NeighborOptions::cells_per_cutoff leaves it to the
/// search) for atoms with `neighbours` neighbours each: cells of a whole cutoff, whose stencil
/// holds about 27 r^3 of candidates, or of half a cutoff, which holds about 16 r^3 but pays a
/// range of a few atoms per stencil row and atom. The range kernel leaves out, for each atom,
/// the end cells of a row whose atoms' bounding box lies beyond the cutoff, which takes much of
/// the larger stencil's surplus away (on random systems 7.3 candidates per pair become 6.5, on
/// diamond 6.5 become 3.4). Halving still wins once rows hold enough atoms: `tricell bench` on
/// random systems (density 0.05 and 0.1, full and half lists) puts the crossing at about 130
/// neighbours (90: whole cells 1.25x faster; 107: 1.19x; 144: half cells 1.05-1.08x faster).
/// Only the dense backend's range kernel gains from it (policy.cpp).
inline double grid_cells_per_cutoff(double neighbours) {
    return neighbours >= 130.0 ? 2.0 : 1.0;
}

/// Dense or hash for a grid search: dense when the full-resolution cell count fits the cap.
inline SearchBackend choose_grid_backend(double full_resolution_cells, double max_cells) {
    return full_resolution_cells <= max_cells ? SearchBackend::dense : SearchBackend::hash;
}

/// The octree's n_max when NeighborOptions::leaf_size is 0.
inline std::size_t octree_leaf_size(const OctreeCosts& costs = OctreeCosts()) {
    return std::size_t(std::max(1.0, std::round(costs.leaf_size)));
}

/// u_grid(rho) of the dense grid or the hash (`grid`), cubic cells of side cutoff.
inline double grid_cost_per_atom(SearchBackend grid, double density, double cutoff,
                                 const OctreeCosts& costs = OctreeCosts()) {
    const double* g = grid == SearchBackend::hash ? costs.hash : costs.dense;
    const double lambda = density * cutoff * cutoff * cutoff;
    const double visits = lambda > 1e-12 ? (1 - std::exp(-lambda)) / lambda : 1.0;
    constexpr double stencil = 27;
    return g[0] + g[1] * stencil * visits + g[2] * stencil * lambda;
}

/// u_oct(rho).
inline double octree_cost_per_atom(double density, double cutoff,
                                   const OctreeCosts& costs = OctreeCosts()) {
    const double x = density * cutoff * cutoff * cutoff;
    const double n = costs.leaf_occupancy;
    const double tests = 8 * n + 24 * std::cbrt(n * n * x) + 6 * detail::pi * std::cbrt(n * x * x) +
                         4 * detail::pi / 3 * x;
    return costs.octree[0] + costs.octree[1] * tests;
}

/// True when u_grid < u_oct at every density rho with rho r^3 from 1e-6 to 16 (r = `cutoff`; the
/// range the constants were fitted over): then no mixture of densities can favour the octree
/// and the automatic choice need not look at the atoms.
inline bool grid_always_cheaper(SearchBackend grid, double cutoff,
                                const OctreeCosts& costs = OctreeCosts()) {
    // Both costs depend on the density only through x = rho r^3, so the answer does not depend
    // on the cutoff; the scan (70 points, each with an exp and two cube roots: about 50k
    // instructions, as much as a whole 1-atom search) is kept per thread for the last grid and
    // constants, since auto asks it on every build.
    struct Memo {
        bool valid = false;
        SearchBackend grid = SearchBackend::dense;
        OctreeCosts costs;
        bool cheaper = false;
    };
    thread_local Memo memo;
    if (memo.valid && memo.grid == grid &&
        std::memcmp(&memo.costs, &costs, sizeof(OctreeCosts)) == 0) {
        return memo.cheaper;
    }
    const double volume = cutoff * cutoff * cutoff;
    bool cheaper = true;
    for (double x = 1e-6; x <= 16; x *= 1.25) { // up to the densest fitted (0.1 /A^3 at 5 A)
        if (grid_cost_per_atom(grid, x / volume, cutoff, costs) >=
            octree_cost_per_atom(x / volume, cutoff, costs)) {
            cheaper = false;
            break;
        }
    }
    memo = Memo{true, grid, costs, cheaper};
    return cheaper;
}

/// f*: below this volume fraction of the dense phase the octree is the cheaper (see above).
inline double octree_crossover(SearchBackend grid, double rho_hi, double rho_lo, double cutoff,
                               const OctreeCosts& costs = OctreeCosts()) {
    const double saved_lo = rho_lo * (grid_cost_per_atom(grid, rho_lo, cutoff, costs) -
                                      octree_cost_per_atom(rho_lo, cutoff, costs));
    const double lost_hi = rho_hi * (octree_cost_per_atom(rho_hi, cutoff, costs) -
                                     grid_cost_per_atom(grid, rho_hi, cutoff, costs));
    if (saved_lo <= 0) {
        return lost_hi < 0 ? 1.0 : 0.0;
    }
    if (lost_hi <= 0) {
        return 1.0;
    }
    return saved_lo / (saved_lo + lost_hi);
}

} // namespace tricell
