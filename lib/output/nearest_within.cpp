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
// with a tie tolerance, those with d <= limit (read by the symmetric rule only).
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

// A pair as its centre ranks it: its distance (compared first) and its index in the columns.
struct Entry {
    double d;
    std::size_t p;
};

// One thread's scratch for ranking a centre: each pair's bucket, the buckets' counts and
// cursors, and the pairs of the buckets that matter in order (with room for the others, dumped).
struct Ranking {
    std::vector<std::uint32_t> bucket_of;
    std::vector<std::size_t> counts, cursors;
    std::vector<Entry> sorted;
};

// Sorts [first, last) by (d, j, S): insertion for the few pairs a bucket holds, else std::sort.
void sort_entries(Entry* first, Entry* last, const PairsView& pairs) {
    const auto less = [&](const Entry& l, const Entry& r) {
        if (l.d != r.d) {
            return l.d < r.d;
        }
        return pairs.key(l.p) < pairs.key(r.p);
    };
    if (last - first > 16) {
        std::sort(first, last, less);
        return;
    }
    for (Entry* e = first + 1; e < last; ++e) {
        const Entry moving = *e;
        Entry* to = e;
        for (; to > first && less(moving, to[-1]); --to) {
            *to = to[-1];
        }
        *to = moving;
    }
}

// Ranks the n pairs of one centre, block[0, n): writes the kept ones, in key order, to
// block[0 ...] and returns their count; fills cut (its k-th key only when the symmetric rule
// reads it). A bucket sort on (d / d_max)^3, about one pair per bucket for uniform density
// (whose pair count grows as the cube of d): the buckets are counted, then only the pairs of the
// buckets up to the k-th pair's (and the tolerance's) are placed and sorted.
std::size_t rank_centre(Entry* block, std::size_t n, const PairsView& pairs,
                        const NeighborOptions& options, Ranking& r, Cut& cut) {
    cut = Cut();
    if (n == 0) {
        return 0;
    }
    std::size_t buckets = 8;
    while (buckets < n && buckets < 4096) {
        buckets *= 2;
    }
    double d_max = 0;
    for (std::size_t t = 0; t < n; ++t) {
        d_max = std::max(d_max, block[t].d);
    }
    const double to_unit = d_max > 0 ? 1.0 / d_max : 0.0;
    // Nondecreasing in d (each rounded step is), so a bucket's pairs all rank after the pairs
    // of lower buckets.
    const auto bucket = [&](double d) {
        const double u = d * to_unit;
        const double x = double(buckets) * (u * u * u);
        return x < double(buckets - 1) ? std::size_t(x) : buckets - 1;
    };
    r.bucket_of.resize(n);
    r.counts.assign(buckets, 0);
    for (std::size_t t = 0; t < n; ++t) {
        const std::size_t b = bucket(block[t].d);
        r.bucket_of[t] = std::uint32_t(b);
        ++r.counts[b];
    }
    r.cursors.resize(buckets);
    r.sorted.resize(2 * n);
    Entry* const sorted = r.sorted.data();
    // Places the pairs of buckets [from, to] from place `at` on, in order (the other pairs go
    // to the dump past n, without a branch), and returns the place after them.
    const auto place = [&](std::size_t from, std::size_t to, std::size_t at) {
        const std::size_t first = at;
        for (std::size_t b = 0; b < buckets; ++b) {
            const bool placed = b >= from && b <= to;
            r.cursors[b] = placed ? at : n;
            at += placed ? r.counts[b] : 0;
        }
        for (std::size_t t = 0; t < n; ++t) {
            sorted[r.cursors[r.bucket_of[t]]++] = block[t];
        }
        for (std::size_t b = from, begin = first; b <= to; begin += r.counts[b++]) {
            sort_entries(sorted + begin, sorted + begin + r.counts[b], pairs);
        }
        return at;
    };
    const std::size_t k = options.max_neighbors;
    if (n <= k) {
        place(0, buckets - 1, 0);
        std::copy(sorted, sorted + n, block);
        return n;
    }
    // The bucket of the k-th pair.
    std::size_t kth_bucket = 0;
    for (std::size_t below = r.counts[0]; below < k; below += r.counts[++kth_bucket]) {
    }
    std::size_t end = place(0, kth_bucket, 0);
    const Entry kth = sorted[k - 1];
    cut.all = false;
    if (options.symmetric) {
        cut.kth = pairs.key(kth.p);
    }
    std::size_t count = k;
    if (options.tie_tolerance > 0) {
        cut.limit = kth.d + options.tie_tolerance;
        const std::size_t last = bucket(cut.limit);
        if (last > kth_bucket) {
            end = place(kth_bucket + 1, last, end);
        }
        while (count < end && sorted[count].d <= cut.limit) {
            ++count;
        }
    }
    std::copy(sorted, sorted + count, block);
    return count;
}

// Negation as the list's reverse pairs carry it: -D exactly, never -0.
double negated(double v) {
    return v == 0.0 ? 0.0 : -v;
}

// Marks an entry of the output order as the reverse of its source pair.
constexpr std::size_t reversed = std::size_t(1) << (8 * sizeof(std::size_t) - 1);

// Rewrites `column` (width values per pair) as out[k] = value(order[k] without the flag, w,
// flagged) for the `count` entries of `order`, through `room` (count * width values).
template <class T, class Value>
void gather(PairArray<T>& column, std::size_t width, const std::size_t* order, std::size_t count,
            unsigned char* room, std::size_t threads, const Value& value) {
    if (column.empty()) {
        return;
    }
    T* to = reinterpret_cast<T*>(room);
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
}

// Calls visit(centre, first, end) for each run [first, end) of consecutive pairs of one centre:
// the search meets a centre's pairs several at a time.
template <class Visit> void for_each_run(const PairArray<std::uint32_t>& is, const Visit& visit) {
    const std::size_t n = is.size();
    for (std::size_t first = 0; first < n;) {
        const std::uint32_t centre = is[first];
        std::size_t end = first + 1;
        while (end < n && is[end] == centre) {
            ++end;
        }
        visit(centre, first, end);
        first = end;
    }
}

} // namespace

void keep_nearest_within(PairColumns& columns, std::size_t atoms, const NeighborOptions& options,
                         std::size_t threads, PairArray<unsigned char>& spare) {
    const std::size_t total = columns.size();
    const PairsView pairs{columns.i.data(), columns.j.data(), columns.shifts.data(),
                          columns.distances.data()};

    // `spare`: first each centre's pairs as (d, index), later the column being gathered; then
    // the output order (at most every pair is kept, also by the symmetric rule: each centre's
    // output is part of its full list).
    const std::size_t widest = std::max<std::size_t>(
        {sizeof(std::uint32_t), columns.shifts.empty() ? 0 : 3 * sizeof(std::int32_t),
         columns.distances.empty() ? 0 : sizeof(double),
         columns.vectors.empty() ? 0 : 3 * sizeof(double)});
    const std::size_t area = total * std::max(sizeof(Entry), widest);
    spare.clear(); // no copy of old contents when it grows
    spare.resize(area + total * sizeof(std::size_t));
    Entry* const entries = reinterpret_cast<Entry*>(spare.data());
    std::size_t* const order = reinterpret_cast<std::size_t*>(spare.data() + area);

    // Grouped by centre: a counting sort on i that moves runs.
    std::vector<std::size_t> offsets(atoms + 1, 0);
    for_each_run(columns.i, [&](std::uint32_t centre, std::size_t first, std::size_t end) {
        offsets[centre + 1] += end - first;
    });
    std::partial_sum(offsets.begin(), offsets.end(), offsets.begin());
    {
        std::vector<std::size_t> cursor(offsets.begin(), offsets.end() - 1);
        for_each_run(columns.i, [&](std::uint32_t centre, std::size_t first, std::size_t end) {
            Entry* to = entries + cursor[centre];
            cursor[centre] += end - first;
            for (std::size_t p = first; p < end; ++p) {
                *to++ = Entry{pairs.d[p], p};
            }
        });
    }

    // Each centre's kept pairs, in key order, at the start of its block.
    std::vector<std::size_t> keep(atoms);
    std::vector<Cut> cuts(atoms);
    parallel_ranges(atoms, threads, [&](std::size_t begin, std::size_t end, std::size_t) {
        Ranking ranking;
        for (std::size_t c = begin; c < end; ++c) {
            keep[c] = rank_centre(entries + offsets[c], offsets[c + 1] - offsets[c], pairs, options,
                                  ranking, cuts[c]);
        }
    });

    // The symmetric rule: the reverse of each kept pair that its other end does not keep, by
    // target centre (a counting sort), each target's in key order.
    std::vector<std::size_t> extra_offsets(atoms + 1, 0);
    std::vector<Entry> extras;
    if (options.symmetric) {
        // One pass over the kept pairs (their other ends are anywhere in the columns).
        std::vector<Entry> missing;
        std::vector<std::uint32_t> targets;
        for (std::size_t c = 0; c < atoms; ++c) {
            for (std::size_t t = 0; t < keep[c]; ++t) {
                const Entry e = entries[offsets[c] + t];
                const std::uint32_t target = pairs.j[e.p];
                if (!cuts[target].keeps(pairs.reverse_key(e.p))) {
                    missing.push_back(e);
                    targets.push_back(target);
                    ++extra_offsets[target + 1];
                }
            }
        }
        std::partial_sum(extra_offsets.begin(), extra_offsets.end(), extra_offsets.begin());
        extras.resize(missing.size());
        std::vector<std::size_t> cursor(extra_offsets.begin(), extra_offsets.end() - 1);
        for (std::size_t m = 0; m < missing.size(); ++m) {
            extras[cursor[targets[m]]++] = missing[m];
        }
        parallel_ranges(atoms, threads, [&](std::size_t begin, std::size_t end, std::size_t) {
            for (std::size_t c = begin; c < end; ++c) {
                std::sort(extras.begin() + std::ptrdiff_t(extra_offsets[c]),
                          extras.begin() + std::ptrdiff_t(extra_offsets[c + 1]),
                          [&](const Entry& l, const Entry& r) {
                              if (l.d != r.d) {
                                  return l.d < r.d;
                              }
                              return pairs.reverse_key(l.p) < pairs.reverse_key(r.p);
                          });
            }
        });
    }

    // The output order: each centre's kept pairs merged with the reverses it gains.
    std::vector<std::size_t> out_offsets(atoms + 1, 0);
    for (std::size_t c = 0; c < atoms; ++c) {
        out_offsets[c + 1] = out_offsets[c] + keep[c] + (extra_offsets[c + 1] - extra_offsets[c]);
    }
    const std::size_t count = out_offsets[atoms];
    parallel_ranges(atoms, threads, [&](std::size_t begin, std::size_t end, std::size_t) {
        for (std::size_t c = begin; c < end; ++c) {
            std::size_t own = 0, gained = extra_offsets[c], to = out_offsets[c];
            const Entry* const kept = entries + offsets[c];
            while (own < keep[c] || gained < extra_offsets[c + 1]) {
                bool take_own = gained == extra_offsets[c + 1];
                if (!take_own && own < keep[c]) {
                    const Entry &mine = kept[own], &theirs = extras[gained];
                    take_own = mine.d != theirs.d ? mine.d < theirs.d
                                                  : pairs.key(mine.p) < pairs.reverse_key(theirs.p);
                }
                order[to++] = take_own ? kept[own++].p : extras[gained++].p | reversed;
            }
        }
    });

    // The columns in that order, through the front of `spare`: j first (a reverse pair's j is
    // its source's i), i last.
    unsigned char* const room = spare.data();
    gather(columns.j, 1, order, count, room, threads,
           [&](std::size_t p, std::size_t, bool flipped) {
               return flipped ? pairs.i[p] : pairs.j[p];
           });
    gather(columns.shifts, 3, order, count, room, threads,
           [&](std::size_t p, std::size_t w, bool flipped) {
               return flipped ? -pairs.s[3 * p + w] : pairs.s[3 * p + w];
           });
    gather(columns.distances, 1, order, count, room, threads,
           [&](std::size_t p, std::size_t, bool) { return pairs.d[p]; });
    const double* vectors = columns.vectors.data();
    gather(columns.vectors, 3, order, count, room, threads,
           [&](std::size_t p, std::size_t w, bool flipped) {
               return flipped ? negated(vectors[3 * p + w]) : vectors[3 * p + w];
           });
    spare.clear(); // the capacity stays for the next call
    columns.i.resize(count);
    for (std::size_t c = 0; c < atoms; ++c) {
        std::fill(columns.i.begin() + std::ptrdiff_t(out_offsets[c]),
                  columns.i.begin() + std::ptrdiff_t(out_offsets[c + 1]), std::uint32_t(c));
    }
    columns.offsets = std::move(out_offsets);
}

} // namespace tricell::detail
