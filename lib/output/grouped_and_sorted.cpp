#include "output/grouped_and_sorted.hpp"

#include "detail/stream_copy.hpp"

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <vector>

namespace tricell::detail {

namespace {

// Fills columns.offsets from the count of pairs of each atom.
void count_offsets(PairColumns& columns, std::size_t atoms) {
    std::vector<std::size_t>& offsets = columns.offsets;
    offsets.assign(atoms + 1, 0);
    for (const std::uint32_t i : columns.i) {
        ++offsets[i + 1];
    }
    std::partial_sum(offsets.begin(), offsets.end(), offsets.begin());
}

// Fills columns.offsets and returns the stable permutation that groups the pairs by i.
std::vector<std::size_t> grouping(PairColumns& columns, std::size_t atoms) {
    count_offsets(columns, atoms);
    const PairArray<std::uint32_t>& is = columns.i;
    std::vector<std::size_t> perm(is.size());
    std::vector<std::size_t> cursor(columns.offsets.begin(), columns.offsets.end() - 1);
    for (std::size_t k = 0; k < is.size(); ++k) {
        perm[cursor[is[k]]++] = k;
    }
    return perm;
}

// Copies n values: a run is a few pairs long (an atom's hits in one stencil row), so it moves four
// values at a time inline rather than through a library call per run (which cost as much as
// the search's own storing).
template <class T> void copy_run(const T* from, std::size_t n, T* to) {
    if (n > 64) {
        std::copy_n(from, n, to);
        return;
    }
    for (; n >= 4; n -= 4, from += 4, to += 4) {
        const T a = from[0], b = from[1], c = from[2], d = from[3];
        to[0] = a, to[1] = b, to[2] = c, to[3] = d;
    }
    for (; n > 0; --n) {
        *to++ = *from++;
    }
}

// Calls on_run(begin, end) for each run of equal values in `is`, in order, while it returns
// true; a run is cut at 2^32 - 1 pairs.
template <class OnRun> void for_each_run(const PairArray<std::uint32_t>& is, const OnRun& on_run) {
    const std::size_t n = is.size();
    for (std::size_t begin = 0; begin < n;) {
        const std::uint32_t atom = is[begin];
        std::size_t end = begin + 1;
        while (end < n && is[end] == atom && end - begin < 0xffffffffu) {
            ++end;
        }
        if (!on_run(begin, end)) {
            return;
        }
        begin = end;
    }
}

// Copies each run of consecutive pairs of one atom in `column` (width values per pair) to the
// place its atom's cursor gives in `spare`, advancing the cursor: a counting sort that moves
// runs, not pairs (the runs are found again from `is` for each column, which costs less than
// storing them). Then the grouped column is copied back over `column` in one sequential pass.
// Both buffers are reused from call to call, so a grouped list in a loop writes into resident
// memory instead of asking the kernel for fresh (zeroed) pages each time; the grouping needs
// room for one column more than the list, never a second list (docs/memory.md).
template <class T>
void scatter_runs(PairArray<T>& column, PairArray<unsigned char>& spare,
                  const PairArray<std::uint32_t>& is, std::vector<std::size_t> cursor,
                  std::size_t width) {
    if (column.empty()) {
        return;
    }
    T* to = reinterpret_cast<T*>(spare.data());
    for_each_run(is, [&](std::size_t begin, std::size_t end) {
        std::size_t& at = cursor[is[begin]];
        copy_run(column.data() + width * begin, width * (end - begin), to + width * at);
        at += end - begin;
        return true;
    });
    stream_copy(column.data(), to, column.size() * sizeof(T));
}

// Runs of at least this many pairs on average are gathered (gather_runs()), shorter ones
// scattered (scatter_runs()), so that the run index takes at most 12 / min_run_pairs bytes a
// pair.
constexpr std::size_t min_run_pairs = 16;

// The runs of consecutive pairs of one atom, in atom order (each atom's in the order the search
// met them): run k is pairs [start[k], start[k] + size[k]) of the list.
struct RunIndex {
    std::vector<std::size_t> start;
    std::vector<std::uint32_t> size;
    bool complete = false; // false: too many runs to index (then nothing is filled in)
};

// Two passes over i: the first counts each atom's runs and pairs (filling `offsets`, the
// grouped list's), the second places each run at its atom's next slot (a counting sort of the
// runs on their atoms).
RunIndex index_runs(const PairArray<std::uint32_t>& is, std::size_t atoms,
                    std::vector<std::size_t>& offsets) {
    RunIndex runs;
    std::vector<std::size_t> slot(atoms + 1, 0); // each atom's next run
    offsets.assign(atoms + 1, 0);
    std::size_t count = 0;
    const std::size_t most = is.size() / min_run_pairs;
    for_each_run(is, [&](std::size_t begin, std::size_t end) {
        ++slot[is[begin] + 1];
        offsets[is[begin] + 1] += end - begin;
        return ++count <= most;
    });
    if (count > most) {
        return runs; // short runs: scattered instead
    }
    std::partial_sum(slot.begin(), slot.end(), slot.begin());
    std::partial_sum(offsets.begin(), offsets.end(), offsets.begin());
    runs.start.resize(count);
    runs.size.resize(count);
    for_each_run(is, [&](std::size_t begin, std::size_t end) {
        const std::size_t k = slot[is[begin]]++;
        runs.start[k] = begin;
        runs.size[k] = std::uint32_t(end - begin);
        return true;
    });
    runs.complete = true;
    return runs;
}

// Copies the runs of `column` (width values per pair) into `spare` in atom order, so the
// grouped column is written sequentially and only the reads jump (each run's lines are
// prefetched a few runs ahead); then copies it back over `column` in one sequential pass.
template <class T>
void gather_runs(PairArray<T>& column, PairArray<unsigned char>& spare, const RunIndex& runs,
                 std::size_t width) {
    if (column.empty()) {
        return;
    }
    constexpr std::size_t ahead = 8;
    T* to = reinterpret_cast<T*>(spare.data());
    const T* from = column.data();
    const std::size_t count = runs.start.size();
    for (std::size_t k = 0; k < count; ++k) {
        if (k + ahead < count) {
            const char* p = reinterpret_cast<const char*>(from + width * runs.start[k + ahead]);
            const std::size_t bytes =
                std::min<std::size_t>(width * runs.size[k + ahead] * sizeof(T), 512);
            for (std::size_t b = 0; b < bytes; b += 64) {
                __builtin_prefetch(p + b);
            }
        }
        const std::size_t n = width * runs.size[k];
        copy_run(from + width * runs.start[k], n, to);
        to += n;
    }
    stream_copy(column.data(), spare.data(), column.size() * sizeof(T));
}

} // namespace

void group_pairs(PairColumns& columns, std::size_t atoms, PairArray<unsigned char>& spare) {
    const PairArray<std::uint32_t>& is = columns.i;
    // The search meets each atom's pairs in runs (a cell's atoms against one stencil row at a
    // time), usually long: they move whole, and i is written from the offsets.
    if (std::is_sorted(is.begin(), is.end())) {
        count_offsets(columns, atoms);
        return; // already grouped (a few atoms, or a search that met the atoms in order)
    }
    const std::size_t widest = std::max(
        {columns.j.size() * sizeof(std::uint32_t), columns.shifts.size() * sizeof(std::int32_t),
         columns.distances.size() * sizeof(double), columns.vectors.size() * sizeof(double)});
    spare.clear(); // no copy of old contents when it grows
    spare.resize(widest);
    const RunIndex runs = index_runs(is, atoms, columns.offsets);
    if (runs.complete) {
        gather_runs(columns.j, spare, runs, 1);
        gather_runs(columns.shifts, spare, runs, 3);
        gather_runs(columns.distances, spare, runs, 1);
        gather_runs(columns.vectors, spare, runs, 3);
    } else {
        count_offsets(columns, atoms);
        const std::vector<std::size_t> cursor(columns.offsets.begin(), columns.offsets.end() - 1);
        scatter_runs(columns.j, spare, is, cursor, 1);
        scatter_runs(columns.shifts, spare, is, cursor, 3);
        scatter_runs(columns.distances, spare, is, cursor, 1);
        scatter_runs(columns.vectors, spare, is, cursor, 3);
    }
    spare.clear(); // the capacity stays for the next call; a copy of the list copies nothing
    for (std::size_t a = 0; a < atoms; ++a) {
        std::fill(columns.i.begin() + std::ptrdiff_t(columns.offsets[a]),
                  columns.i.begin() + std::ptrdiff_t(columns.offsets[a + 1]), std::uint32_t(a));
    }
}

void sort_pairs(PairColumns& columns, std::size_t atoms) {
    std::vector<std::size_t> perm = grouping(columns, atoms);
    const PairArray<std::uint32_t>& js = columns.j;
    const PairArray<std::int32_t>& ss = columns.shifts;
    auto before = [&](std::size_t l, std::size_t r) {
        if (js[l] != js[r]) {
            return js[l] < js[r];
        }
        for (std::size_t a = 0; a < 3; ++a) {
            if (ss[3 * l + a] != ss[3 * r + a]) {
                return ss[3 * l + a] < ss[3 * r + a];
            }
        }
        return false;
    };
    const std::vector<std::size_t>& offsets = columns.offsets;
    for (std::size_t i = 0; i < atoms; ++i) {
        std::sort(perm.begin() + std::ptrdiff_t(offsets[i]),
                  perm.begin() + std::ptrdiff_t(offsets[i + 1]), before);
    }
    columns.permute(perm);
}

} // namespace tricell::detail
