#include "policy/list_limits.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "tricell/error.hpp"

namespace tricell {

namespace detail {

namespace {

// The most pairs p with p * per_pair + fixed <= limit (0 when none fit; the callers treat a
// limit of 0 pairs as "at most 0", see below).
std::size_t pairs_within(double limit, double fixed, double per_pair) {
    const double p = std::floor((limit - fixed) / per_pair);
    return p < 0 ? 0 : std::size_t(std::min(p, 0x1p62));
}

} // namespace

double ListMemory::peak(double pairs, std::size_t atoms) const {
    return pairs * (per_pair + order_per_pair) + double(atoms) * per_atom;
}

double ListMemory::growing(double pairs) const {
    return pairs * (per_pair + widest);
}

std::string ListMemory::columns() const {
    return cat("i, j", shifts ? ", S" : "", distances ? ", d" : "", vectors ? ", D" : "");
}

std::string ListMemory::rates() const {
    std::string text = cat(per_pair, " bytes a pair of ", columns());
    if (order_per_pair > 0) {
        text += cat(" + ", order_per_pair, " a pair to ", order, " them + ", per_atom, " an atom");
    }
    return text;
}

ListMemory list_memory(const NeighborOptions& options) {
    const Quantities& q = options.quantities;
    ListMemory m;
    m.per_pair = 8;
    m.widest = 4;
    const auto add = [&](bool stored, bool& flag, double bytes) {
        flag = stored;
        if (stored) {
            m.per_pair += bytes;
            m.widest = std::max(m.widest, bytes);
        }
    };
    const bool nearest = options.max_neighbors != 0;
    add(q.shifts || options.sorted || nearest, m.shifts, 12);
    add(q.distances || nearest, m.distances, 8);
    add(q.vectors, m.vectors, 24);
    if (nearest) {
        // Each pair's (d, index) grouped by centre (16), later the column being gathered in
        // the same room, and the output order (8 a kept pair, at most every pair), with the
        // symmetric rule the reverses gained (8 at most a pair); per atom the offsets, a cursor,
        // each centre's count and cut (40) and the output's offsets (and the reverses' two).
        m.order_per_pair = std::max(16.0, m.widest) + 8 + (options.symmetric ? 8 : 0);
        m.per_atom = 8 + 8 + 8 + 40 + 8 + (options.symmetric ? 16 : 0);
        m.order = "select";
    } else if (options.sorted) {
        m.order_per_pair = 8 + m.widest; // the permutation, one column being permuted
        m.per_atom = 16;                 // the offsets, a cursor
        m.order = "sort";
    } else if (options.grouped) {
        // One column being regrouped, and the index of the runs it is gathered by (at most 12
        // bytes a run of 16 pairs on average).
        m.order_per_pair = m.widest + 1;
        m.per_atom = 16; // the offsets, each atom's next run (or pair)
        m.order = "group";
    }
    return m;
}

ListLimits::ListLimits(const NeighborOptions& options, std::size_t atoms, const char* subject)
    : memory_(list_memory(options)), subject_(subject), atoms_(atoms),
      max_pairs_(options.max_pairs), max_bytes_(options.max_bytes), pairs_(options.max_pairs) {
    if (max_bytes_ == 0) {
        return;
    }
    // A limit of 0 pairs means "no limit" to the stores, so a list of which no pair fits is
    // held to 1 pair (refused at its second).
    const double fixed = double(atoms) * memory_.per_atom;
    const std::size_t fit = std::max<std::size_t>(
        1, pairs_within(double(max_bytes_), fixed, memory_.per_pair + memory_.order_per_pair));
    pairs_ = pairs_ == 0 ? fit : std::min(pairs_, fit);
    growing_ = std::max<std::size_t>(
        1, pairs_within(double(max_bytes_), 0, memory_.per_pair + memory_.widest));
}

void ListLimits::check_estimate(double pairs, double cutoff) const {
    const double bytes = memory_.peak(pairs, atoms_);
    const bool over_pairs = max_pairs_ != 0 && pairs > double(max_pairs_);
    if (!over_pairs && (max_bytes_ == 0 || bytes <= double(max_bytes_))) {
        return; // the text below is composed only for a refusal
    }
    const std::string subject = cat("cutoff ", cutoff, " would give about ", pairs, " pairs for ",
                                    atoms_, " atoms (estimated from the density)");
    if (over_pairs) {
        throw PairLimitError(subject, pairs, max_pairs_);
    }
    throw PairLimitError(
        cat(subject, ", ", std::llround(bytes), " bytes at its peak (", memory_.rates(), ")"),
        pairs, bytes, max_bytes_);
}

void ListLimits::fail_size(std::size_t size) const {
    if (max_pairs_ != 0 && size > max_pairs_) {
        throw PairLimitError(subject_, double(size), max_pairs_);
    }
    const double bytes = memory_.peak(double(size), atoms_);
    throw PairLimitError(cat(subject_, ": ", size, " pairs are ", std::llround(bytes),
                             " bytes at their peak (", memory_.rates(), ")"),
                         double(size), bytes, max_bytes_);
}

void ListLimits::fail_growth(std::size_t size) const {
    const double bytes = memory_.growing(double(size));
    throw PairLimitError(cat("the neighbour list outgrew its estimate: growing its columns of ",
                             size, " pairs needs ", std::llround(bytes), " bytes (",
                             memory_.per_pair, " bytes a pair of ", memory_.columns(), " + ",
                             memory_.widest, " a pair while a column is copied)"),
                         double(size), bytes, max_bytes_);
}

} // namespace detail
} // namespace tricell
