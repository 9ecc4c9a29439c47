// Verlet lists: a neighbour list with a skin, rebuilt only when the motion since the last build
// could have brought a new pair inside the cutoff, plus the cost model that picks the skin.
//
// A build runs the neighbour search (NeighborSearch) once at the list radius r_l = r_c + skin
// and keeps the candidate pairs (i, j, S). Each later update() does not search: it measures how
// far every atom has moved since the build, and if that motion is within budget it filters the
// candidates down to the pairs with |D| < r_c for the current positions and box, with fresh S,
// d and D, in buffers that survive between calls. Otherwise it rebuilds first (and says so).
//
// The rebuild rule is DisplacementTracker's (include/tricell/displacement.hpp: the rule, why it
// is safe, why displacements are fractional); the refreshed image shift S' = S + m_j - m_i, m the
// tracker's jumps, keeps S relative to the caller's positions as given.
//
// Cost model. A build costs C_b (the search at r_l), every step costs C_f (the displacement check
// plus filtering the candidates, whose number grows as r_l^3), and the list survives about
// 1 + skin / (2 v) steps, v the largest displacement per step. The cost per step,
//     C(skin) = C_b(r_l, h) / (1 + skin / (2 v)) + C_f(r_l),
// is minimised numerically over the skin and the cell size h (see SkinCostModel). With only the
// r_l^3 terms (C_b = B r_l^3, C_f = F r_l^3) the optimum is y = skin* + 2 v, the positive root of
//     3 F y^2 + 4 v B y - 2 v B (r_c - 2 v) = 0,   i.e.   skin* ~ sqrt(2 v B r_c / (3 F))
// for small v: the skin grows as the square root of the speed and of the build-to-filter ratio.
// benchmarks/verlet_bench.cpp measures the costs, fits the model and checks its choice.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "tricell/box.hpp"
#include "tricell/displacement.hpp"
#include "tricell/export.hpp"
#include "tricell/neighbor_list.hpp"
#include "tricell/types.hpp"

namespace tricell {

struct TRICELL_API VerletOptions {
    /// The search of a build and what update() reports: neighbors.cutoff is r_c (pairs with
    /// |D| < r_c, strict), neighbors.half, neighbors.quantities (what is stored per pair besides
    /// i and j), the backend, threads of the search, max_pairs and max_bytes (limits on the
    /// CANDIDATES of a build) and max_cells. neighbors.cells_per_cutoff counts cells per LIST
    /// radius r_l = r_c + skin (h = r_l / k, k >= 1, or 0 for the search's choice; 1 gives
    /// h = r_l, r_l / r_c gives h = r_c; 2 by default, see SkinCostModel); it never changes the
    /// result. neighbors.sorted and
    /// neighbors.grouped are ignored (update() always groups the pairs by i). Variable cutoffs
    /// (radii, species_cutoffs) are not supported by the Verlet list.
    NeighborOptions neighbors = default_neighbors();
    /// Delta: candidates are built at r_c + skin. Finite and >= 0 (0 rebuilds whenever
    /// anything moves).
    double skin = 0;

    /// Throws InvalidArgument naming the offending field and value.
    void validate() const;

  private:
    static NeighborOptions default_neighbors() {
        NeighborOptions o;
        o.cells_per_cutoff = 2;
        return o;
    }
};

/// A Verlet list: candidates at cutoff + skin, refreshed to the pairs within the cutoff.
///
///     tricell::VerletList list(options);
///     for (step...) { move(x); bool rebuilt = list.update(box, x); use(list); }
///
/// After update() the stored pairs are grouped by i in increasing order (offsets() gives each
/// atom's range); the order of an atom's pairs is unspecified.
class TRICELL_API VerletList {
  public:
    VerletList() = default;
    /// Validates the options.
    explicit VerletList(const VerletOptions& options);

    const VerletOptions& options() const { return options_; }
    /// r_l = cutoff + skin, the radius the candidates are built at.
    double list_radius() const { return options_.neighbors.cutoff + options_.skin; }

    /// Refreshes the pairs within the cutoff for these positions and box, rebuilding the
    /// candidates first when needs_rebuild(). Returns true if it rebuilt. Positions may lie
    /// anywhere and may be wrapped (or shifted by any lattice vector) between calls. On error
    /// the stored pairs are left empty and the next update() rebuilds.
    bool update(const Box& box, PointsView positions);
    /// Rebuilds the candidates unconditionally, then refreshes as update() does.
    void rebuild(const Box& box, PointsView positions);
    /// Pairs of a subset (NeighborOptions::query, checked at the next build): replaces
    /// options().neighbors.query and forgets the candidates, so the next update() rebuilds.
    void set_query(std::optional<std::vector<std::uint32_t>> query);

    /// True when the candidates may miss a pair: nothing built yet, a different atom count or
    /// periodicity, or some atom displaced (minimum image, build frame) by more than
    /// displacement_budget(box). Throws InvalidArgument for a non-finite position.
    bool needs_rebuild(const Box& box, PointsView positions) const;
    /// (skin - eps r_c) / 2 with eps = max(0, ||H0 H^-1|| - 1): how far each atom may have moved
    /// since the build for the candidates to stay complete in this box. Negative (a rebuild is
    /// needed whatever the positions) when nothing is built or the periodicity changed.
    double displacement_budget(const Box& box) const;
    /// Largest displacement of an atom since the build (minimum image in the build box of the
    /// fractional displacement). Infinity when nothing is built or the atom count or
    /// periodicity differs.
    double max_displacement(const Box& box, PointsView positions) const;
    /// Forgets the candidates (the next update() rebuilds) and the stored pairs. Keeps buffers.
    void reset();

    /// The pairs of the last update() as a NeighborList (i, j, S, d, D as asked for in the
    /// options), grouped by i: pairs().offsets() is filled.
    const NeighborList& pairs() const { return pairs_; }
    std::size_t size() const { return pairs_.size(); }

    /// Builds so far (each update() that rebuilt, and each rebuild()).
    std::size_t rebuild_count() const { return rebuild_count_; }
    /// Candidate pairs of the current build (at the list radius).
    std::size_t candidate_count() const { return candidate_j_.size(); }
    /// Refreshes since the last build (0 right after a build).
    std::size_t updates_since_build() const { return updates_since_build_; }

  private:
    void build(const Box& box, PointsView positions);
    void refresh(const Box& box);
    void clear_pairs();

    VerletOptions options_;

    // The build: the tracker (box, wrapped fractional positions s0), candidates by i (CSR) with
    // an index into a dense table of their shifts S0 relative to the wrapped build positions.
    DisplacementTracker tracker_;
    NeighborList raw_;
    std::vector<std::size_t> candidate_offsets_;
    PairArray<std::uint32_t> candidate_j_;
    PairArray<std::uint32_t> candidate_shift_;
    PairArray<std::int32_t> scratch_;       // S0 per raw candidate, during a build
    std::vector<std::size_t> cursor_;       // counting-sort cursors, during a build
    std::vector<std::int32_t> shift_table_; // 3 ints per entry
    std::vector<double> shift_vectors_;     // H S per entry, for the box of shift_box_
    Eigen::Matrix3d shift_box_ = Eigen::Matrix3d::Zero();

    // The last update: per-atom jumps m (3 ints) and unwrapped positions x + H m (3 doubles).
    std::vector<std::int32_t> jumps_;
    std::vector<double> unwrapped_;

    NeighborList pairs_;

    std::size_t rebuild_count_ = 0;
    std::size_t updates_since_build_ = 0;
};

} // namespace tricell
