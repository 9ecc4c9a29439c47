#include "output/nearest_within.hpp"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <limits>
#include <numeric>
#include <vector>

#include "detail/pair_rank.hpp"
#include "detail/parallel.hpp"

namespace tricell::detail {

namespace {

// A pair's rank within its centre (detail/pair_rank.hpp).
using Key = RankedPair;

// What a centre keeps: every pair (a centre of at most k pairs), or those up to its k-th key and,
// with a tie tolerance, those with d <= limit.
struct Cut {
    bool all = true;
    Key kth{};
    double limit = -std::numeric_limits<double>::infinity();
    bool keeps(const Key& key) const { return all || !(kth < key) || key.d <= limit; }
};

// The pairs' columns as the selection reads them.
struct PairsView {
    const std::uint32_t* i;
    const std::uint32_t* j;
    const std::int32_t* s;
    const double* d;

    Key key(std::size_t p) const { return {d[p], j[p], {s[3 * p], s[3 * p + 1], s[3 * p + 2]}}; }
    // The key of the reverse pair (j, i, -S) at centre j (same d: the list's reverse is exact).
    Key reverse_key(std::size_t p) const {
        return {d[p], i[p], {-s[3 * p], -s[3 * p + 1], -s[3 * p + 2]}};
    }
};

// Marks an entry of the output order as the reverse of its source pair.
constexpr std::size_t reversed = std::size_t(1) << (8 * sizeof(std::size_t) - 1);

// A pair of the block being ranked: its distance and its place in the block.
struct Entry {
    double d;
    std::uint32_t local;
};

// Ranks the pairs of centre c, [begin, end): writes the kept ones' places in the block, in key
// order, to kept[begin ...], and returns their count; fills cut.
std::size_t select_centre(const PairsView& pairs, std::size_t begin, std::size_t end,
                          const NeighborOptions& options, std::vector<Entry>& entries,
                          std::uint32_t* kept, Cut& cut) {
    const std::size_t n = end - begin;
    entries.resize(n);
    for (std::size_t t = 0; t < n; ++t) {
        entries[t] = Entry{pairs.d[begin + t], std::uint32_t(t)};
    }
    const auto less = [&](const Entry& l, const Entry& r) {
        if (l.d != r.d) {
            return l.d < r.d;
        }
        return pairs.key(begin + l.local) < pairs.key(begin + r.local);
    };
    const std::size_t k = options.max_neighbors;
    std::size_t count = n;
    cut = Cut();
    if (n > k) {
        std::nth_element(entries.begin(), entries.begin() + std::ptrdiff_t(k - 1), entries.end(),
                         less);
        const Entry kth = entries[k - 1];
        cut.all = false;
        cut.kth = pairs.key(begin + kth.local);
        count = k;
        if (options.tie_tolerance > 0) {
            cut.limit = kth.d + options.tie_tolerance;
            const auto tail = std::partition(entries.begin() + std::ptrdiff_t(k), entries.end(),
                                             [&](const Entry& e) { return e.d <= cut.limit; });
            count = std::size_t(tail - entries.begin());
        }
    }
    std::sort(entries.begin(), entries.begin() + std::ptrdiff_t(count), less);
    for (std::size_t t = 0; t < count; ++t) {
        kept[begin + t] = entries[t].local;
    }
    return count;
}

// Negation as the list's reverse pairs carry it: -D exactly, never -0.
double negated(double v) {
    return v == 0.0 ? 0.0 : -v;
}

// Rewrites `column` (width values per pair) as out[k] = value(order[k] without the flag, w,
// flagged), through `spare`.
template <class T, class Value>
void gather(PairArray<T>& column, std::size_t width, const std::vector<std::size_t>& order,
            PairArray<unsigned char>& spare, std::size_t threads, const Value& value) {
    if (column.empty()) {
        return;
    }
    const std::size_t count = order.size();
    spare.clear();
    spare.resize(count * width * sizeof(T));
    T* to = reinterpret_cast<T*>(spare.data());
    parallel_ranges(count, threads, [&](std::size_t begin, std::size_t end, std::size_t) {
        for (std::size_t k = begin; k < end; ++k) {
            const std::size_t source = order[k] & ~reversed;
            const bool flipped = (order[k] & reversed) != 0;
            for (std::size_t w = 0; w < width; ++w) {
                to[width * k + w] = value(source, w, flipped);
            }
        }
    });
    column.resize(count * width);
    if (count > 0) {
        std::memcpy(column.data(), to, count * width * sizeof(T));
    }
    spare.clear();
}

} // namespace

void keep_nearest_within(PairColumns& columns, std::size_t atoms, const NeighborOptions& options,
                         std::size_t threads, PairArray<unsigned char>& spare) {
    const std::size_t total = columns.size();
    const PairsView pairs{columns.i.data(), columns.j.data(), columns.shifts.data(),
                          columns.distances.data()};
    const std::vector<std::size_t>& offsets = columns.offsets;

    // Each centre's kept pairs, in key order, at the start of its block.
    std::vector<std::uint32_t> kept(total);
    std::vector<std::size_t> keep(atoms);
    std::vector<Cut> cuts(atoms);
    parallel_ranges(atoms, threads, [&](std::size_t begin, std::size_t end, std::size_t) {
        std::vector<Entry> entries;
        for (std::size_t c = begin; c < end; ++c) {
            keep[c] = select_centre(pairs, offsets[c], offsets[c + 1], options, entries,
                                    kept.data(), cuts[c]);
        }
    });

    // The symmetric rule: the reverse of each kept pair that its other end does not keep, by
    // target centre (a counting sort), each target's in key order.
    std::vector<std::size_t> extra_offsets(atoms + 1, 0);
    std::vector<std::size_t> extras;
    if (options.symmetric) {
        const auto for_each_missing_reverse = [&](auto&& visit) {
            for (std::size_t c = 0; c < atoms; ++c) {
                for (std::size_t t = 0; t < keep[c]; ++t) {
                    const std::size_t p = offsets[c] + kept[offsets[c] + t];
                    const std::uint32_t target = pairs.j[p];
                    if (!cuts[target].keeps(pairs.reverse_key(p))) {
                        visit(target, p);
                    }
                }
            }
        };
        for_each_missing_reverse(
            [&](std::uint32_t target, std::size_t) { ++extra_offsets[target + 1]; });
        std::partial_sum(extra_offsets.begin(), extra_offsets.end(), extra_offsets.begin());
        extras.resize(extra_offsets[atoms]);
        std::vector<std::size_t> cursor(extra_offsets.begin(), extra_offsets.end() - 1);
        for_each_missing_reverse(
            [&](std::uint32_t target, std::size_t p) { extras[cursor[target]++] = p; });
        parallel_ranges(atoms, threads, [&](std::size_t begin, std::size_t end, std::size_t) {
            for (std::size_t c = begin; c < end; ++c) {
                std::sort(extras.begin() + std::ptrdiff_t(extra_offsets[c]),
                          extras.begin() + std::ptrdiff_t(extra_offsets[c + 1]),
                          [&](std::size_t l, std::size_t r) {
                              return pairs.reverse_key(l) < pairs.reverse_key(r);
                          });
            }
        });
    }

    // The output order: each centre's kept pairs merged with the reverses it gains.
    std::vector<std::size_t> out_offsets(atoms + 1, 0);
    for (std::size_t c = 0; c < atoms; ++c) {
        out_offsets[c + 1] = out_offsets[c] + keep[c] + (extra_offsets[c + 1] - extra_offsets[c]);
    }
    std::vector<std::size_t> order(out_offsets[atoms]);
    parallel_ranges(atoms, threads, [&](std::size_t begin, std::size_t end, std::size_t) {
        for (std::size_t c = begin; c < end; ++c) {
            std::size_t own = 0, gained = extra_offsets[c], to = out_offsets[c];
            const std::size_t first = offsets[c];
            while (own < keep[c] || gained < extra_offsets[c + 1]) {
                const bool take_own = gained == extra_offsets[c + 1] ||
                                      (own < keep[c] && pairs.key(first + kept[first + own]) <
                                                            pairs.reverse_key(extras[gained]));
                order[to++] = take_own ? first + kept[first + own++] : extras[gained++] | reversed;
            }
        }
    });
    kept = std::vector<std::uint32_t>();

    // The columns in that order: j first (a reverse pair's j is its source's i), i last.
    gather(columns.j, 1, order, spare, threads, [&](std::size_t p, std::size_t, bool flipped) {
        return flipped ? pairs.i[p] : pairs.j[p];
    });
    gather(columns.shifts, 3, order, spare, threads,
           [&](std::size_t p, std::size_t w, bool flipped) {
               return flipped ? -pairs.s[3 * p + w] : pairs.s[3 * p + w];
           });
    gather(columns.distances, 1, order, spare, threads,
           [&](std::size_t p, std::size_t, bool) { return pairs.d[p]; });
    const double* vectors = columns.vectors.data();
    gather(columns.vectors, 3, order, spare, threads,
           [&](std::size_t p, std::size_t w, bool flipped) {
               return flipped ? negated(vectors[3 * p + w]) : vectors[3 * p + w];
           });
    columns.i.resize(order.size());
    for (std::size_t c = 0; c < atoms; ++c) {
        std::fill(columns.i.begin() + std::ptrdiff_t(out_offsets[c]),
                  columns.i.begin() + std::ptrdiff_t(out_offsets[c + 1]), std::uint32_t(c));
    }
    columns.offsets = std::move(out_offsets);
}

} // namespace tricell::detail
