// The adaptive octree backend (an adaptive grid: cells refined where the atoms are dense): a tree
// over fractional space whose leaves hold at most n_max atoms, so cells are small where the atoms
// are dense and large (or absent) where they are sparse, and memory is O(N) whatever the volume.
//
// Build. The root is the atoms' tight bounding box in fractional coordinates (within [0, 1) on
// periodic axes, the atoms' extent on open ones). A node with more than n_max atoms is split at
// the midpoint of its tight box across its longest edge |a_k| (u_k - l_k) (across all the tied
// longest edges at once, so a cube splits eight ways and every three levels make the eight-way
// split of a round cell); each child keeps the tight box of its own atoms. Halving one edge at a
// time keeps a leaf's occupancy within a factor two of n_max (an eight-way split lets it fall to
// n_max / 8, and the cost of the search with it, in steps of eight as N grows), and a slab splits
// across its wide edges until its cells are round. Empty children are not stored, and a
// midpoint always separates the lowest atom from the highest along a split axis, so every split
// yields at least two children and nodes < 2 leaves <= 2 N. Atoms that cannot be separated
// (coincident, or beyond the depth limit) stay together in one leaf. Atoms are stored in
// depth-first leaf order, so every node is one contiguous range of atoms and of leaves.
//
// Candidates. A node pair (A, B) through an image shift S is kept when the closest approach of
// the fractional box B + S - A in the triclinic metric (box_within_radius, after a cheap lower
// bound from the perpendicular widths; a plain sum of squared gaps when the lattice vectors are
// at right angles) is below the search radius. The tree is descended once per shift for the
// highest ancestor P holding at most eight leaves, collecting the leaves B that P reaches; each
// leaf A of P then keeps those of them its own box reaches (a two-level dual-tree descent: the top
// of the tree is walked once per group of leaves, not once per leaf). The shifts are those for
// which the root can reach itself (all images within the radius, several when the cutoff exceeds
// the box; S = 0 on open axes). A full list takes every surviving (A, B, S), with `own` for (A, A,
// 0). A half list (or a full one found through the half stencil, BuildPlan::mirrored) takes each
// unordered pair once: for S = 0 only leaves B >= A (B == A: b > a), and for S != 0 only S
// lexicographically positive, with every (A, B) including A == B and a == b (an atom and its own
// image). The pair (b, a, -S) of (a, b, S) lies in (B, A, -S), whose box is the negated one, so
// pruning keeps both or neither and this choice loses nothing. Consecutive leaves found with one
// shift are adjacent in the atom order and are scanned as one range. The work units are the leaves;
// a leaf's candidates depend on that leaf only, so any split of the units gives the same pairs in
// the same order.
#include <algorithm>
#include <array>
#include <cmath>

#include "backends/backend.hpp"
#include "policy/cost_model.hpp"
#include "tricell/stencil.hpp"

namespace tricell::detail {

namespace {

// Deeper than any useful split (each level halves one edge: 2^-32 of the box); a guard against
// adversarial inputs.
constexpr int depth_limit = 96;
// Leaves that share one descent of the tree (see visit()).
constexpr std::uint32_t group_leaves = 8;

struct Node {
    Eigen::Vector3d lo = Eigen::Vector3d::Zero(); // tight fractional box of the node's atoms
    Eigen::Vector3d hi = Eigen::Vector3d::Zero();
    std::uint32_t begin = 0, end = 0;            // atoms [begin, end) in the backend's order
    std::uint32_t first_leaf = 0, last_leaf = 0; // leaves [first_leaf, last_leaf]
    std::uint32_t first_child = 0;
    std::uint32_t children = 0; // 0 for a leaf
};

class OctreeBackend final : public Backend {
  public:
    void bin(const BinningInput& input, std::vector<std::uint32_t>& order) override {
        const std::size_t n = input.fractional.size();
        h_ = input.frame.matrix();
        widths_ = input.frame.perpendicular_widths();
        for (int k = 0; k < 3; ++k) {
            edge_[k] = h_.col(k).norm();
        }
        gram_ = h_.transpose() * h_;
        const Eigen::Matrix3d& gram = gram_;
        // At right angles up to rounding (90 degrees from parameters is cos = 6e-17): the error of
        // the orthogonal formula is then far below the search radius's margin.
        auto square = [&](int i, int j) {
            return std::abs(gram(i, j)) <= 1e-12 * std::sqrt(gram(i, i) * gram(j, j));
        };
        orthogonal_ = square(0, 1) && square(0, 2) && square(1, 2);
        radius_ = input.search_radius;
        radius_sq_ = radius_ * radius_;
        half_ = input.plan.half_stencil(input.options);
        leaf_size_ = input.options.leaf_size != 0 ? input.options.leaf_size : octree_leaf_size();
        nodes_.clear();
        leaves_.clear();
        order.resize(n);
        for (std::size_t i = 0; i < n; ++i) {
            order[i] = std::uint32_t(i);
        }
        scratch_.resize(n);
        nodes_.reserve(2 * (n / std::max<std::size_t>(1, leaf_size_)) + 16);
        nodes_.emplace_back();
        nodes_[0].begin = 0;
        nodes_[0].end = std::uint32_t(n);
        // The root's region: [0, 1) on periodic axes, the atoms' extent on open ones. Each split
        // halves a node's region at the midpoint of its atoms' tight box.
        Eigen::Vector3d region_lo = input.lower, region_hi = input.upper;
        for (int k = 0; k < 3; ++k) {
            if (input.frame.periodicity()[k]) {
                region_lo[k] = 0;
                region_hi[k] = 1;
            }
        }
        leaf_volume_.clear();
        split(0, 0, region_lo, region_hi, input.fractional, order);
        std::vector<std::uint32_t> parent(nodes_.size(), 0);
        for (std::uint32_t id = 0; id < nodes_.size(); ++id) {
            for (std::uint32_t c = 0; c < nodes_[id].children; ++c) {
                parent[nodes_[id].first_child + c] = id;
            }
        }
        // Each leaf's group: its highest ancestor with at most group_leaves leaves.
        group_.resize(leaves_.size());
        for (std::size_t l = 0; l < leaves_.size(); ++l) {
            std::uint32_t g = parent[leaves_[l]];
            while (g != 0 && leaf_count(parent[g]) <= group_leaves) {
                g = parent[g];
            }
            group_[l] = g;
        }
        scratch_.clear();
        scratch_.shrink_to_fit();
        choose_shifts(input.frame.periodicity());
    }

    std::size_t unit_count() const override { return leaves_.size(); }

    void occupancy(UnitOccupancy& out) const override {
        out.atoms.resize(leaves_.size());
        for (std::size_t l = 0; l < leaves_.size(); ++l) {
            const Node& leaf = nodes_[leaves_[l]];
            out.atoms[l] = double(leaf.end - leaf.begin);
        }
        out.volume.assign(leaf_volume_.begin(), leaf_volume_.end());
    }

    // The average number of candidate leaves, from a few evenly spaced leaves.
    double neighbours() const override {
        const std::size_t samples = std::min<std::size_t>(leaves_.size(), 32);
        double total = 0;
        for (std::size_t k = 0; k < samples; ++k) {
            const std::size_t l = k * leaves_.size() / samples;
            for (const std::array<int, 3>& shift : shifts_) {
                descend(nodes_[leaves_[l]], std::uint32_t(l), shift,
                        [&](std::uint32_t) { total += 1; });
            }
        }
        return samples > 0 ? total / double(samples) : 0;
    }

    void visit(std::size_t begin, std::size_t end, CandidateScanner& scan) const override {
        std::vector<ImageShift> images;
        images.reserve(shifts_.size());
        for (const std::array<int, 3>& s : shifts_) {
            images.push_back(scan.shift(s[0], s[1], s[2]));
        }
        // The candidates (shift, leaf) of the leaf's group, shared by the group's leaves, each of
        // which keeps those its own box reaches.
        std::vector<std::pair<std::uint32_t, std::uint32_t>> group;
        std::uint32_t group_node = std::uint32_t(-1);
        for (std::size_t l = begin; l < end; ++l) {
            const std::uint32_t id = leaves_[l];
            const Node& a = nodes_[id];
            if (group_[l] != group_node) {
                group_node = group_[l];
                group.clear();
                const Node& p = nodes_[group_node];
                for (std::uint32_t k = 0; k < shifts_.size(); ++k) {
                    descend(p, p.first_leaf, shifts_[k],
                            [&](std::uint32_t leaf) { group.emplace_back(k, leaf); });
                }
            }
            // Runs of consecutive leaves [first, last] through one shift k.
            std::uint32_t k = 0, first = 0, last = 0;
            bool run = false;
            auto flush = [&] {
                if (run) {
                    const bool own = is_zero(shifts_[k]) && first <= l && l <= last;
                    scan.ranges(a.begin, a.end, nodes_[leaves_[first]].begin,
                                nodes_[leaves_[last]].end, images[k], own);
                }
            };
            for (const auto& [shift, leaf] : group) {
                if (half_ && leaf < l && is_zero(shifts_[shift])) {
                    continue;
                }
                if (!reachable(a, nodes_[leaves_[leaf]], shifts_[shift])) {
                    continue;
                }
                if (run && shift == k && leaf == last + 1) {
                    last = leaf;
                    continue;
                }
                flush();
                run = true;
                k = shift;
                first = last = leaf;
            }
            flush();
        }
    }

    void describe(SearchInfo& info) const override {
        info.backend = SearchBackend::octree;
        info.cells = {{1, 1, 1}};
        info.stored_cells = leaves_.size();
    }

  private:
    std::uint32_t leaf_count(std::uint32_t id) const {
        return nodes_[id].last_leaf - nodes_[id].first_leaf + 1;
    }

    static bool is_zero(const std::array<int, 3>& s) { return s[0] == 0 && s[1] == 0 && s[2] == 0; }

    static bool lexicographically_positive(const std::array<int, 3>& s) {
        if (s[0] != 0) {
            return s[0] > 0;
        }
        if (s[1] != 0) {
            return s[1] > 0;
        }
        return s[2] > 0;
    }

    // Can a point of box b (shifted by s) come closer than the radius to a point of box a?
    bool reachable(const Node& a, const Node& b, const std::array<int, 3>& s) const {
        Eigen::Vector3d lower, upper, gap;
        for (int k = 0; k < 3; ++k) {
            lower[k] = b.lo[k] + s[std::size_t(k)] - a.hi[k];
            upper[k] = b.hi[k] + s[std::size_t(k)] - a.lo[k];
            // |u_k| w_k <= |H u|: a gap across one pair of faces is a lower bound.
            gap[k] = lower[k] > 0 ? lower[k] : (upper[k] < 0 ? -upper[k] : 0.0);
            if (gap[k] * widths_[k] >= radius_) {
                return false;
            }
        }
        if (gap.isZero()) {
            return true; // the boxes touch or overlap (even when radius_sq_ underflows to 0)
        }
        if (orthogonal_) { // the gaps are orthogonal: the closest approach is their sum
            return gap.cwiseProduct(widths_).squaredNorm() < radius_sq_;
        }
        return box_within_radius(h_, gram_, edge_, lower, upper, radius_);
    }

    // Calls found(leaf) for every leaf B that box a reaches through shift s, in leaf order (half
    // lists with s = 0: only leaves B >= later_than).
    template <class Found>
    void descend(const Node& a, std::uint32_t later_than, const std::array<int, 3>& s,
                 Found&& found) const {
        const bool only_later = half_ && is_zero(s);
        std::uint32_t stack[8 * depth_limit + 8];
        std::size_t top = 0;
        stack[top++] = 0;
        while (top > 0) {
            const Node& b = nodes_[stack[--top]];
            if ((only_later && b.last_leaf < later_than) || !reachable(a, b, s)) {
                continue;
            }
            if (b.children == 0) {
                found(b.first_leaf);
                continue;
            }
            for (std::uint32_t c = b.children; c-- > 0;) { // pushed in reverse: popped in order
                stack[top++] = b.first_child + c;
            }
        }
    }

    // Splits node `id` (atoms order[begin, end)) until its leaves hold at most leaf_size_ atoms.
    // `region` is the part of space the node stands for (its leaves' regions tile the root's).
    void split(std::uint32_t id, int depth, const Eigen::Vector3d& region_lo,
               const Eigen::Vector3d& region_hi, const PairArray<Eigen::Vector3d>& frac,
               std::vector<std::uint32_t>& order) {
        const std::uint32_t begin = nodes_[id].begin, end = nodes_[id].end;
        Eigen::Vector3d lo = frac[order[begin]], hi = lo;
        for (std::uint32_t k = begin + 1; k < end; ++k) {
            lo = lo.cwiseMin(frac[order[k]]);
            hi = hi.cwiseMax(frac[order[k]]);
        }
        nodes_[id].lo = lo;
        nodes_[id].hi = hi;
        nodes_[id].first_leaf = std::uint32_t(leaves_.size());
        auto make_leaf = [&] {
            nodes_[id].children = 0;
            nodes_[id].last_leaf = nodes_[id].first_leaf;
            leaves_.push_back(id);
            // Fractional volume of the leaf's region; an axis without extent (atoms in a plane
            // of an open axis) counts as one search radius thick, as in the pair estimate.
            double volume = 1;
            for (int k = 0; k < 3; ++k) {
                const double extent = region_hi[k] - region_lo[k];
                volume *= extent > 0 ? extent : radius_ / widths_[k];
            }
            leaf_volume_.push_back(volume);
        };
        if (std::size_t(end - begin) <= leaf_size_ || depth >= depth_limit) {
            make_leaf();
            return;
        }
        // The axis to halve: the longest edge (all of them when tied, as in a cube).
        double longest = 0;
        Eigen::Vector3d length;
        for (int k = 0; k < 3; ++k) {
            length[k] = (hi[k] - lo[k]) * edge_[k];
            longest = std::max(longest, length[k]);
        }
        if (!(longest > 0)) {
            make_leaf(); // coincident atoms
            return;
        }
        Eigen::Vector3d mid;
        bool cut[3];
        for (int k = 0; k < 3; ++k) {
            cut[k] = length[k] == longest;
            mid[k] = lo[k] + 0.5 * (hi[k] - lo[k]);
        }
        auto octant = [&](std::uint32_t atom) {
            unsigned key = 0;
            for (int k = 0; k < 3; ++k) {
                key = 2 * key + (cut[k] && frac[atom][k] >= mid[k] ? 1u : 0u);
            }
            return key;
        };
        std::array<std::uint32_t, 9> start{};
        for (std::uint32_t k = begin; k < end; ++k) {
            ++start[octant(order[k]) + 1];
        }
        int nonempty = 0;
        for (int o = 0; o < 8; ++o) {
            nonempty += start[std::size_t(o) + 1] > 0 ? 1 : 0;
            start[std::size_t(o) + 1] += start[std::size_t(o)];
        }
        if (nonempty < 2) {
            make_leaf(); // the midpoint did not separate them (rounding at tiny extents)
            return;
        }
        std::array<std::uint32_t, 8> cursor;
        std::copy(start.begin(), start.begin() + 8, cursor.begin());
        for (std::uint32_t k = begin; k < end; ++k) {
            scratch_[begin + cursor[octant(order[k])]++] = order[k];
        }
        std::copy(scratch_.begin() + begin, scratch_.begin() + end, order.begin() + begin);

        const std::uint32_t first_child = std::uint32_t(nodes_.size());
        std::array<unsigned, 8> octants{};
        for (unsigned o = 0; o < 8; ++o) {
            if (start[o + 1] > start[o]) {
                Node child;
                child.begin = begin + start[o];
                child.end = begin + start[o + 1];
                octants[nodes_.size() - first_child] = o;
                nodes_.push_back(child);
            }
        }
        nodes_[id].first_child = first_child;
        nodes_[id].children = std::uint32_t(nonempty);
        for (std::uint32_t c = 0; c < std::uint32_t(nonempty); ++c) {
            Eigen::Vector3d child_lo = region_lo, child_hi = region_hi;
            for (int k = 0; k < 3; ++k) {
                if (cut[k]) {
                    const bool upper_half = ((octants[c] >> (2 - k)) & 1u) != 0;
                    (upper_half ? child_lo : child_hi)[k] = mid[k];
                }
            }
            split(first_child + c, depth + 1, child_lo, child_hi, frac, order);
        }
        nodes_[id].last_leaf = std::uint32_t(leaves_.size()) - 1;
    }

    // Every image shift through which the root can reach itself (in lexicographic order); for a
    // half list only S = 0 and the lexicographically positive ones.
    void choose_shifts(const Periodicity& pbc) {
        shifts_.clear();
        std::array<int, 3> reach{};
        for (int k = 0; k < 3; ++k) {
            reach[std::size_t(k)] = pbc[k]
                                        ? checked_image_reach(std::ceil(radius_ / widths_[k]) + 1,
                                                              radius_, widths_[k], k)
                                        : 0;
        }
        const Node& root = nodes_[0];
        std::array<int, 3> s;
        for (s[0] = -reach[0]; s[0] <= reach[0]; ++s[0]) {
            for (s[1] = -reach[1]; s[1] <= reach[1]; ++s[1]) {
                for (s[2] = -reach[2]; s[2] <= reach[2]; ++s[2]) {
                    if (half_ && !is_zero(s) && !lexicographically_positive(s)) {
                        continue;
                    }
                    if (reachable(root, root, s)) {
                        shifts_.push_back(s);
                    }
                }
            }
        }
    }

    Eigen::Matrix3d h_ = Eigen::Matrix3d::Identity();
    Eigen::Matrix3d gram_ = Eigen::Matrix3d::Identity(); // H^T H
    Eigen::Vector3d widths_ = Eigen::Vector3d::Ones();
    Eigen::Vector3d edge_ = Eigen::Vector3d::Ones();
    double radius_ = 0, radius_sq_ = 0;
    bool half_ = false;
    bool orthogonal_ = false; // lattice vectors at right angles
    std::size_t leaf_size_ = 8;
    std::vector<Node> nodes_;
    std::vector<std::uint32_t> group_;  // the node whose candidates each leaf filters
    std::vector<double> leaf_volume_;   // fractional volume of each leaf's region
    std::vector<std::uint32_t> leaves_; // node of each leaf, in atom order
    std::vector<std::array<int, 3>> shifts_;
    std::vector<std::uint32_t> scratch_;
};

} // namespace

std::unique_ptr<Backend> make_octree_backend() {
    return std::make_unique<OctreeBackend>();
}

} // namespace tricell::detail
