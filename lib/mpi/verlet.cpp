// The distributed Verlet list (tricell/mpi/verlet.hpp): the rebuild vote, the build of oriented
// candidates (the list's rule applied once per build) and the filter of each update() (the one
// both Verlet lists run, detail/verlet_filter.hpp).
#include "tricell/mpi/verlet.hpp"

#include <cmath>
#include <exception>
#include <numeric>
#include <string>

#include "collective.hpp"
#include "detail/candidate_radius.hpp"
#include "detail/verlet_filter.hpp"
#include "pair_map.hpp"
#include "scan/distance_kernel.hpp"
#include "tricell/error.hpp"

namespace tricell::mpi {

namespace {

// The distributed list's candidates for the refresh filter (detail/verlet_filter.hpp): the
// oriented pairs (owned a, local b) of the build, b at its image among the halo's local
// positions, so that D = y_b - y_a; written as (a, b), their global ids and S = c_a - c_b
// (halo.hpp), relative to the owners' caller positions.
template <bool Shifts> struct OwnedCandidates {
    const std::uint32_t* cand_b;
    const double* y;
    const std::uint64_t* ids;
    const std::int32_t* images;
    detail::ColumnPointers out;

    tricell::detail::Point origin(std::size_t a) const {
        return {y[3 * a], y[3 * a + 1], y[3 * a + 2]};
    }

    tricell::detail::Point partner(std::size_t p) const {
        const std::size_t b = cand_b[p];
        return {y[3 * b], y[3 * b + 1], y[3 * b + 2]};
    }

    void write(std::size_t slot, std::size_t a, std::size_t p) const {
        // Every read before the first write: a write through out.i may alias ids.
        const std::size_t b = cand_b[p];
        const std::uint64_t id_a = ids[a];
        const std::uint64_t id_b = ids[b];
        out.owned[slot] = std::uint32_t(a);
        out.local_j[slot] = std::uint32_t(b);
        out.i[slot] = id_a;
        out.j[slot] = id_b;
        if constexpr (Shifts) {
            for (std::size_t k = 0; k < 3; ++k) {
                out.shifts[3 * slot + k] = images[3 * a + k] - images[3 * b + k];
            }
        }
    }
};

void add_exchange(const Halo& halo, Traffic& to) {
    to.add(std::uint64_t(halo.stats().messages_sent), std::uint64_t(halo.stats().bytes_sent));
}

void add_values(const Halo& halo, Traffic& to) {
    to.add(std::uint64_t(halo.comm_messages_sent()), std::uint64_t(halo.comm_bytes_sent()));
}

} // namespace

DistributedVerletList::DistributedVerletList(const VerletOptions& options) : options_(options) {
    options_.validate();
}

void DistributedVerletList::reset() {
    built_ = false;
    tracker_.reset();
    candidate_offsets_.clear();
    candidate_b_.clear();
    pairs_.clear();
}

bool DistributedVerletList::update(const Decomposition& decomposition, const Box& box,
                                   LocalAtoms& atoms) {
    // On an error (thrown on every rank alike) the build is forgotten and the pairs emptied, as
    // the serial list does: the next update() rebuilds.
    try {
        const MPI_Comm comm = decomposition.comm();
        const Box open = Box::from_columns(box.matrix(), Periodicity::none());

        // Can the build still serve? Every rank must say yes, in the one MPI_Allreduce of a
        // step: the input check and the vote of the owned atoms (a ghost moved as its owner
        // did, whose rank checks it). The ghosts' new positions are sent only when it serves.
        int keep = built_ && atoms.size() == halo_.owned_count() &&
                   box.periodicity() == built_periodicity_;
        detail::agreed(
            comm,
            [&] {
                atoms.validate();
                if (keep) {
                    halo_.place_owned(box, atoms.points());
                    keep = !tracker_.needs_rebuild(
                        open, PointsView(halo_.positions().data(), halo_.owned_count()),
                        options_.skin, options_.neighbors.cutoff);
                }
            },
            &keep);
        if (keep) {
            halo_.send_positions(decomposition, box);
            add_exchange(halo_, traffic_.halo_update);
        } else {
            built_ = false;
            // Among the last halo's neighbour ranks when every atom's owner is one of them (an atom
            // moves less than the halo reach in a Verlet interval), else MPI_Alltoall.
            if (!halo_built_ ||
                !migrate(decomposition, box, atoms, halo_.neighbor_ranks(), &traffic_.migration)) {
                if (!halo_built_) {
                    migrate(decomposition, box, atoms);
                }
                ++alltoall_migrations_;
            }
            halo_.build(decomposition, box, atoms.ids, atoms.points(), list_radius(), nullptr,
                        nullptr, options_.neighbors.half ? GhostSet::upper : GhostSet::all);
            add_exchange(halo_, traffic_.halo_build);
            halo_built_ = true;
            build(decomposition, open);
            built_ = true;
            built_periodicity_ = box.periodicity();
            ++rebuild_count_;
        }
        refresh();
        return !keep;
    } catch (...) {
        reset();
        throw;
    }
}

void DistributedVerletList::build(const Decomposition& decomposition, const Box& open) {
    const std::size_t owned = halo_.owned_count();
    const PointsView local = halo_.points();
    detail::agreed(decomposition.comm(), [&] {
        options_.validate();
        // Pairs of the owned atoms only (the first of the local atoms): no ghost-ghost pair.
        NeighborOptions search = options_.neighbors;
        search.cutoff = tricell::detail::candidate_radius(list_radius(), open.matrix(), local);
        std::vector<std::uint32_t> query(owned);
        std::iota(query.begin(), query.end(), 0u);
        search.query = std::move(query);
        search.half = true;
        search.sorted = false;
        search.grouped = false;
        search.quantities = Quantities{false, false, false};
        search_.build(open, local, search);
        search_.compute(raw_);
        tracker_.record(open, PointsView(halo_.positions().data(), owned));
    });
    // The list's rule once per local pair: (owned i, local j) in the orientation reported.
    detail::map_pairs(raw_, halo_, options_.neighbors.half, false, Quantities{false, false, false},
                      oriented_);
    raw_.clear();
    // Grouped by owned i (counting sort, each atom's candidates in the search's order).
    const std::size_t count = oriented_.size();
    candidate_offsets_.assign(owned + 1, 0);
    for (std::size_t p = 0; p < count; ++p) {
        ++candidate_offsets_[oriented_.owned[p] + 1];
    }
    std::partial_sum(candidate_offsets_.begin(), candidate_offsets_.end(),
                     candidate_offsets_.begin());
    std::vector<std::size_t> cursor(candidate_offsets_.begin(), candidate_offsets_.end() - 1);
    candidate_b_.resize(count);
    for (std::size_t p = 0; p < count; ++p) {
        candidate_b_[cursor[oriented_.owned[p]]++] = oriented_.local_j[p];
    }
    oriented_.clear();
}

void DistributedVerletList::refresh() {
    const Quantities& q = options_.neighbors.quantities;
    const std::size_t capacity = candidate_b_.size();
    DistributedPairs& out = pairs_;
    const detail::ColumnPointers columns =
        detail::resize_columns(out, capacity, q.shifts, q.distances, q.vectors);
    const double cutoff_sq = tricell::detail::strict_threshold_sq(options_.neighbors.cutoff);
    const std::size_t n =
        tricell::detail::with_columns(q, [&](auto shifts, auto distances, auto vectors) {
            const OwnedCandidates<decltype(shifts)::value> candidates{
                candidate_b_.data(), halo_.positions().data(), halo_.ids().data(),
                halo_.images().data(), columns};
            return tricell::detail::filter_candidates<decltype(distances)::value,
                                                      decltype(vectors)::value>(
                candidates, halo_.owned_count(), candidate_offsets_.data(), cutoff_sq,
                columns.distances, columns.vectors, nullptr);
        });
    detail::resize_columns(out, n, q.shifts, q.distances, q.vectors);
}

void DistributedVerletList::forward(const Decomposition& decomposition, const Box& box,
                                    const LocalAtoms& atoms) {
    halo_.update(decomposition, box, atoms.points());
    add_exchange(halo_, traffic_.halo_update);
}

void DistributedVerletList::forward_values(const Decomposition& decomposition,
                                           std::vector<double>& values, std::size_t width) const {
    halo_.forward(decomposition, values, width);
    add_values(halo_, traffic_.forward);
}

void DistributedVerletList::reverse_sum(const Decomposition& decomposition,
                                        std::vector<double>& values, std::size_t width) const {
    halo_.reverse_sum(decomposition, values, width);
    add_values(halo_, traffic_.reverse_sum);
}

} // namespace tricell::mpi
