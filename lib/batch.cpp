#include "tricell/batch.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <exception>
#include <limits>

#include "detail/parallel.hpp"
#include "policy/list_limits.hpp"
#include "policy/policy.hpp"
#include "search/search_state.hpp"
#include "tricell/error.hpp"

namespace tricell {

namespace detail {

// One thread's state: a search reused from structure to structure (and from call to call), a
// scratch list for ordered lists, the columns its run of structures is appended to (thread 0
// appends straight to the output), and per structure of the run its pair count and, when
// grouped or sorted, the per-atom offsets relative to the structure's first pair.
struct BatchWorker {
    SearchState search;
    NeighborList scratch;
    PairColumns columns;
    std::vector<std::size_t> pairs;
    std::vector<std::size_t> offsets;
};

// Rethrows the exception in flight with "structure s: " before its message, keeping its type.
[[noreturn]] void rethrow_for_structure(std::size_t s) {
    try {
        throw;
    } catch (const PairLimitError& e) {
        throw e.with_subject(cat("structure ", s, ": ", e.subject()));
    } catch (const InvalidArgument& e) {
        detail::fail<InvalidArgument>("structure ", s, ": ", e.what());
    } catch (const GeometryError& e) {
        detail::fail<GeometryError>("structure ", s, ": ", e.what());
    } catch (const Error& e) {
        detail::fail<Error>("structure ", s, ": ", e.what());
    }
}

} // namespace detail

namespace {

// Appends all of `from` to `to`.
template <class T> void append(PairArray<T>& to, const PairArray<T>& from) {
    to.insert(to.end(), from.begin(), from.end());
}

// Appends all of `from` to `to`, each index plus `shift`.
void append(PairArray<std::uint32_t>& to, const PairArray<std::uint32_t>& from,
            std::uint32_t shift) {
    const std::size_t at = to.size();
    to.resize(at + from.size());
    for (std::size_t k = 0; k < from.size(); ++k) {
        to[at + k] = from[k] + shift;
    }
}

// Adds `shift` to i and j of the pairs from `start` on.
void shift_indices(PairColumns& c, std::size_t start, std::uint32_t shift) {
    for (std::size_t k = start; k < c.size(); ++k) {
        c.i[k] += shift;
        c.j[k] += shift;
    }
}

// Copies `count` pairs of `from` from its pair `at` to `to` from its pair `to_at` (the columns
// `to` holds, sized already).
void copy_pairs(const PairColumns& from, std::size_t at, std::size_t count, PairColumns& to,
                std::size_t to_at) {
    const auto copy = [&](const auto& source, auto& target, std::size_t width) {
        if (!source.empty()) {
            std::copy_n(source.begin() + std::ptrdiff_t(width * at), width * count,
                        target.begin() + std::ptrdiff_t(width * to_at));
        }
    };
    copy(from.i, to.i, 1);
    copy(from.j, to.j, 1);
    copy(from.shifts, to.shifts, 3);
    copy(from.distances, to.distances, 1);
    copy(from.vectors, to.vectors, 3);
}

using detail::run_in_threads; // detail/parallel.hpp

} // namespace

BatchList::BatchList() = default;
BatchList::~BatchList() = default;
BatchList::BatchList(BatchList&&) noexcept = default;
BatchList& BatchList::operator=(BatchList&&) noexcept = default;

void BatchList::clear() {
    columns_.clear();
    pair_offsets_.clear();
    atom_offsets_.clear();
}

void compute_neighbors_batch(const BatchStructure* structures, std::size_t count,
                             const NeighborOptions& options, BatchList& out, BatchIndices indices) {
    out.clear();
    out.indices_ = indices;
    options.validate();
    if (count > 0 && structures == nullptr) {
        detail::fail<InvalidArgument>("structures: null data for ", count, " structures");
    }
    const Quantities& q = options.quantities;
    // The whole batch's list is held to max_pairs and max_bytes (with every structure's atoms).
    std::size_t all_atoms = 0;
    for (std::size_t s = 0; s < count; ++s) {
        all_atoms += structures[s].positions.size();
    }
    const bool global = indices == BatchIndices::global;
    if (global && all_atoms > std::numeric_limits<std::uint32_t>::max()) {
        detail::fail<InvalidArgument>("global indices number at most ",
                                      std::numeric_limits<std::uint32_t>::max(),
                                      " atoms, but the batch has ", all_atoms);
    }
    const detail::ListLimits limits(options, all_atoms, "the batch has too many pairs in total");
    std::vector<double> cost(count);
    for (std::size_t s = 0; s < count; ++s) {
        cost[s] =
            detail::structure_cost(structures[s].box, structures[s].positions.size(), options);
    }
    const std::vector<std::size_t> bounds = detail::plan_structure_runs(cost, options);
    const std::size_t runs = bounds.size() - 1;

    NeighborOptions one = options; // each structure's search runs on its worker's thread
    one.threads = 1;
    // An unordered list is searched straight into the batch's columns; a grouped, sorted or
    // nearest list into a scratch list that is then appended.
    const bool in_place = !options.with_offsets();
    // A uniform cutoff's rule does not depend on the structure: set once per worker.
    const bool rule_once = !options.variable_cutoff();
    std::vector<detail::BatchWorker> workers;
    workers.swap(out.workers_);
    workers.resize(runs);
    // Lowest index of a structure that failed so far; a worker stops at its first failure and
    // skips structures above the lowest one known, so the lowest failing index is reported
    // whatever the thread count (every structure below it is still searched).
    std::atomic<std::size_t> first_failure{std::numeric_limits<std::size_t>::max()};
    std::vector<std::exception_ptr> errors(runs);
    std::vector<std::size_t> failed_at(runs, std::numeric_limits<std::size_t>::max());

    auto run = [&](std::size_t t) {
        detail::BatchWorker& w = workers[t];
        PairColumns& columns = t == 0 ? out.columns_ : w.columns;
        columns.clear();
        w.pairs.clear();
        w.offsets.clear();
        w.search.options = one;
        if (rule_once) {
            w.search.rule.set(one, 0);
        }
        // The first atom of the run's first structure among all atoms of the batch.
        std::size_t first_atom = 0;
        for (std::size_t s = 0; s < bounds[t]; ++s) {
            first_atom += structures[s].positions.size();
        }
        for (std::size_t s = bounds[t]; s < bounds[t + 1]; ++s) {
            const auto atom_shift = std::uint32_t(global ? first_atom : 0);
            first_atom += structures[s].positions.size();
            if (s > first_failure.load(std::memory_order_relaxed)) {
                return;
            }
            try {
                detail::build_search(w.search, structures[s].box, structures[s].positions, 1,
                                     rule_once);
                const std::size_t start = columns.size();
                if (in_place) {
                    detail::append_pairs(w.search, columns, limits);
                    if (atom_shift != 0) {
                        shift_indices(columns, start, atom_shift);
                    }
                } else {
                    w.scratch.clear();
                    detail::compute_list(w.search, w.scratch);
                    const NeighborList& list = w.scratch;
                    if (limits.pairs() != 0 && columns.size() + list.size() > limits.pairs()) {
                        limits.fail_size(columns.size() + list.size());
                    }
                    append(columns.i, list.i(), atom_shift);
                    append(columns.j, list.j(), atom_shift);
                    append(columns.shifts, list.shifts());
                    append(columns.distances, list.distances());
                    append(columns.vectors, list.vectors());
                    w.offsets.insert(w.offsets.end(), list.offsets().begin(),
                                     list.offsets().end() - (list.offsets().empty() ? 0 : 1));
                }
                w.pairs.push_back(columns.size() - start);
            } catch (...) {
                try {
                    detail::rethrow_for_structure(s);
                } catch (...) {
                    errors[t] = std::current_exception();
                }
                failed_at[t] = s;
                std::size_t known = first_failure.load();
                while (s < known && !first_failure.compare_exchange_weak(known, s)) {
                }
                return;
            }
        }
    };

    const detail::TeamScope team(runs); // its helpers search the runs, then join them
    try {
        run_in_threads(runs, run);
        const auto lowest = std::min_element(failed_at.begin(), failed_at.end());
        if (*lowest != std::numeric_limits<std::size_t>::max()) {
            std::rethrow_exception(errors[std::size_t(lowest - failed_at.begin())]);
        }

        // Offsets per structure, in structure order (the runs are contiguous and in order).
        out.pair_offsets_.assign(count + 1, 0);
        out.atom_offsets_.assign(count + 1, 0);
        std::vector<std::size_t> run_start(runs, 0);
        std::size_t total = 0;
        for (std::size_t t = 0; t < runs; ++t) {
            run_start[t] = total;
            for (std::size_t k = 0; k < workers[t].pairs.size(); ++k) {
                total += workers[t].pairs[k];
                out.pair_offsets_[bounds[t] + k + 1] = total;
            }
        }
        for (std::size_t s = 0; s < count; ++s) {
            out.atom_offsets_[s + 1] = out.atom_offsets_[s] + structures[s].positions.size();
        }
        if (limits.pairs() != 0 && total > limits.pairs()) {
            limits.fail_size(total);
        }

        // Join the other runs' columns after run 0's: their pairs, in structure order, cut into
        // one equal piece per thread.
        if (runs > 1) {
            PairColumns& c = out.columns_;
            c.i.resize(total);
            c.j.resize(total);
            if (q.shifts) {
                c.shifts.resize(3 * total);
            }
            if (q.distances) {
                c.distances.resize(total);
            }
            if (q.vectors) {
                c.vectors.resize(3 * total);
            }
            const std::size_t first = run_start[1], joined = total - first;
            run_in_threads(runs, [&](std::size_t k) {
                const std::size_t lo = first + joined * k / runs;
                const std::size_t hi = first + joined * (k + 1) / runs;
                for (std::size_t t = 1; t < runs; ++t) {
                    const std::size_t begin = std::max(lo, run_start[t]);
                    const std::size_t end = std::min(hi, run_start[t] + workers[t].columns.size());
                    if (begin < end) {
                        copy_pairs(workers[t].columns, begin - run_start[t], end - begin, c, begin);
                    }
                }
            });
        }

        if (options.with_offsets()) {
            // Per-atom offsets, shifted from each structure's first pair to the shared columns.
            out.columns_.offsets.reserve(out.atom_offsets_[count] + 1);
            for (std::size_t t = 0; t < runs; ++t) {
                std::size_t atom = 0;
                for (std::size_t s = bounds[t]; s < bounds[t + 1]; ++s) {
                    const std::size_t atoms = structures[s].positions.size();
                    for (std::size_t a = 0; a < atoms; ++a) {
                        out.columns_.offsets.push_back(out.pair_offsets_[s] +
                                                       workers[t].offsets[atom + a]);
                    }
                    atom += atoms;
                }
            }
            out.columns_.offsets.push_back(total);
        }
        for (detail::BatchWorker& w : workers) {
            w.columns.clear();
        }
        out.workers_.swap(workers);
    } catch (...) {
        out.clear();
        out.workers_.swap(workers);
        throw;
    }
}

void compute_neighbors_batch(const std::vector<BatchStructure>& structures,
                             const NeighborOptions& options, BatchList& out, BatchIndices indices) {
    compute_neighbors_batch(structures.data(), structures.size(), options, out, indices);
}

} // namespace tricell
