#include "policy/policy.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <thread>

#include "detail/parallel.hpp"
#include "detail/pi.hpp"
#include "policy/cost_model.hpp"

namespace tricell::detail {

namespace {

// The processor's threads, asked once: the C library reads them from the file system on every
// call, which costs a tiny search many times its own work.
std::size_t hardware_threads() {
    static const std::size_t threads =
        std::max<std::size_t>(1, std::thread::hardware_concurrency());
    return threads;
}

std::size_t compute_threads(const NeighborOptions& options, double estimated_pairs,
                            std::size_t units) {
    std::size_t threads = options.threads > 0 ? std::size_t(options.threads) : hardware_threads();
    // With automatic threads, small searches are not worth a thread.
    if (options.threads == 0 && (estimated_pairs < 20000 || units < 4 * threads)) {
        threads = 1;
    }
    return std::max<std::size_t>(1, std::min(threads, units));
}

std::size_t cell_cap(const NeighborOptions& options, std::size_t atoms) {
    return options.max_cells != 0 ? options.max_cells : 4 * atoms + 64;
}

// The concrete backend for `automatic` (see the comment atop policy.hpp).
SearchBackend automatic_backend(const Box& box, const PairArray<Eigen::Vector3d>& fractional,
                                const Eigen::Vector3d& lower, const Eigen::Vector3d& upper,
                                double search_radius, double cells_per_cutoff,
                                const NeighborOptions& options) {
    const std::size_t n = fractional.size();
    double min_width = std::numeric_limits<double>::infinity();
    for (int k = 0; k < 3; ++k) {
        if (box.periodic(k)) {
            min_width = std::min(min_width, box.perpendicular_widths()[k]);
        }
    }
    if (choose_direct(n, min_width, search_radius)) {
        return SearchBackend::direct;
    }
    const double h = search_radius / cells_per_cutoff;
    double cells = 1;
    for (int k = 0; k < 3; ++k) {
        const double span = box.periodic(k) ? 1.0 : std::max(upper[k] - lower[k], 0.0);
        cells *= std::max(1.0, std::floor(span * box.perpendicular_widths()[k] / h));
    }
    const SearchBackend grid = choose_grid_backend(cells, double(cell_cap(options, n)));
    const OctreeCosts costs;
    if (grid_always_cheaper(grid, search_radius, costs)) {
        return grid; // at no density does the octree win: no need to look at the atoms
    }

    // The two-density model's T in its general form: each structure's cost per atom u(rho)
    // summed over the atoms, each at its local density, estimated from a sample of at most 4096
    // atoms binned in coarse cells of side >= 2 r (keys sorted, runs counted).
    std::array<double, 3> origin{}, scale{};
    std::array<std::uint64_t, 3> dims{};
    double cell_volume = box.volume();
    for (int k = 0; k < 3; ++k) {
        const std::size_t a = std::size_t(k);
        const double span = box.periodic(k) ? 1.0 : upper[k] - lower[k];
        const double width = span * box.perpendicular_widths()[k];
        dims[a] = std::uint64_t(std::clamp(std::floor(width / (2 * search_radius)), 1.0, 1e6));
        origin[a] = box.periodic(k) ? 0.0 : lower[k];
        scale[a] = span > 0 ? double(dims[a]) / span : 0.0;
        // An open axis thinner than the cutoff counts as one cutoff thick (as the pair estimate).
        cell_volume *=
            (box.periodic(k) ? 1.0
                             : std::max(span, search_radius / box.perpendicular_widths()[k])) /
            double(dims[a]);
    }
    const std::size_t samples = std::min<std::size_t>(n, 4096);
    std::vector<std::uint64_t> keys(samples);
    for (std::size_t t = 0; t < samples; ++t) {
        const Eigen::Vector3d& s = fractional[t * n / samples];
        std::uint64_t key = 0;
        for (std::size_t a = 0; a < 3; ++a) {
            // NaN when a denormal span made the scale inf and an atom sits at the origin
            // (0 * inf): that atom is in cell 0.
            const double c = std::floor((s[int(a)] - origin[a]) * scale[a]);
            key = key * dims[a] +
                  std::uint64_t(std::clamp(std::isnan(c) ? 0.0 : c, 0.0, double(dims[a] - 1)));
        }
        keys[t] = key;
    }
    std::sort(keys.begin(), keys.end());
    const double weight = double(n) / double(samples);
    double grid_cost = 0, octree_cost = 0;
    for (std::size_t t = 0; t < samples;) {
        std::size_t u = t;
        while (u < samples && keys[u] == keys[t]) {
            ++u;
        }
        const double count = double(u - t);
        // The atom itself, plus the others of its cell the sample stands for.
        const double density = (1 + (count - 1) * weight) / cell_volume;
        grid_cost += count * grid_cost_per_atom(grid, density, search_radius, costs);
        octree_cost += count * octree_cost_per_atom(density, search_radius, costs);
        t = u;
    }
    // Only a clear win (30%): the per-cell estimate reads the surface cells of a dense cluster as
    // vapour, which overstates the octree's gain, and the fitted costs scatter by about 20%.
    return octree_cost < 0.7 * grid_cost ? SearchBackend::octree : grid;
}

// Expected stored pairs of a whole system: the density over the region the atoms occupy (an
// open axis counts as at least one cutoff thick); what max_pairs is checked against.
double estimated_system_pairs(const Box& box, std::size_t atoms, const Eigen::Vector3d& lower,
                              const Eigen::Vector3d& upper, double cutoff, bool half) {
    double volume = box.volume();
    for (int k = 0; k < 3; ++k) {
        if (!box.periodic(k)) {
            volume *= std::max(upper[k] - lower[k], cutoff / box.perpendicular_widths()[k]);
        }
    }
    const double sphere = sphere_volume(cutoff);
    // The whole system's n^2 sphere / V, kept in this order (the estimate is reported); NaN when
    // sphere and volume both underflowed: no estimate (the sink still enforces max_pairs on the
    // real count).
    const double pairs = double(atoms) * double(atoms) * sphere / volume * (half ? 0.5 : 1.0);
    return std::isnan(pairs) ? 0 : pairs;
}

// The most pairs a list of `query_atoms` centres among `atoms` can hold within `search_radius`:
// each centre pairs with every atom in every image the cutoff reaches. Wrapped, two atoms'
// fractional separation along a periodic axis of width w is below 1 in size, so at most
// ceil(2 r / w) + 1 images are within r along it; an open axis has one. Infinite when that
// count overflows. Only reserves are capped by it: a huge cutoff over a few atoms, or an open
// molecule, never reserves room for millions of pairs.
double possible_pairs(const Box& box, std::size_t atoms, std::size_t query_atoms,
                      double search_radius, bool half) {
    double images = 1;
    for (int k = 0; k < 3; ++k) {
        if (box.periodic(k)) {
            images *= std::ceil(2 * search_radius / box.perpendicular_widths()[k]) + 1;
        }
    }
    return double(query_atoms) * double(atoms) * images * (half ? 0.5 : 1.0);
}

// The batches of `units` units with `expected[u]` expected pairs and `work[u]` occupancy work
// each, for `threads` threads (at least four batches per thread), of a list that holds at most
// `most_pairs`.
BatchPlan plan_batches(const PairArray<double>& work, const PairArray<double>& expected,
                       std::size_t threads, double most_pairs) {
    // About batch_pairs pairs a batch: with i, j, S, d about 230 KB of columns, which stay in
    // the core's L2 until they are copied out.
    constexpr double batch_pairs = 8192;
    double total = 0;
    for (const double e : expected) {
        total += e;
    }
    const double wanted = std::isfinite(total) ? std::ceil(total / batch_pairs) : 1e9;
    const auto batches = static_cast<std::size_t>(std::clamp(wanted, 4.0 * double(threads), 1e9));
    BatchPlan plan;
    plan.bounds = split_work(work, batches);
    plan.reserve.resize(plan.bounds.size() - 1);
    for (std::size_t b = 0; b + 1 < plan.bounds.size(); ++b) {
        double e = 0;
        for (std::size_t u = plan.bounds[b]; u < plan.bounds[b + 1]; ++u) {
            e += expected[u];
        }
        plan.reserve[b] = pair_room(e <= most_pairs ? e : most_pairs);
    }
    return plan;
}

} // namespace

std::size_t pair_room(double expected, std::size_t limit) {
    const double cap = limit != 0 ? double(limit) : double(std::size_t(1) << 24);
    return std::isfinite(expected) && expected * 1.1 + 1024 < cap
               ? static_cast<std::size_t>(expected * 1.1) + 1024
               : static_cast<std::size_t>(cap);
}

std::size_t build_threads(const NeighborOptions& options, std::size_t atoms) {
    // Explicit threads from 16 atoms per thread (so that the property tests run the threaded
    // phases on small systems); automatic ones from 16384, where a phase outweighs waking a
    // thread.
    return options.threads > 0 ? threads_for(atoms, std::size_t(options.threads), 16)
                               : threads_for(atoms, hardware_threads(), 16384);
}

std::size_t call_threads(const NeighborOptions& options) {
    return options.threads > 0 ? std::size_t(options.threads) : hardware_threads();
}

bool BuildPlan::exact_pruning(double cells) const {
    // Solving one offset's closest approach costs about 1000 instructions, an offset leads to
    // about N^2 / C / 5 distance tests.
    return double(atoms) * double(atoms) / cells > 200;
}

BuildPlan plan_build(const NeighborOptions& options, const Box& frame,
                     const WrappedPositions& wrapped, double cutoff, double search_radius,
                     std::size_t query_atoms) {
    const std::size_t n = wrapped.fractional.size();
    const bool subset = query_atoms < n;
    BuildPlan plan;
    plan.threads = build_threads(options, n);
    plan.atoms = n;
    plan.cell_cap = cell_cap(options, n);
    // A subset search's pairs are estimated as the query's share of the full list's.
    plan.most_pairs = possible_pairs(frame, n, query_atoms, search_radius, options.half && !subset);
    plan.estimated_pairs = std::min(estimated_system_pairs(frame, n, wrapped.lower, wrapped.upper,
                                                           cutoff, options.half && !subset) *
                                        (double(query_atoms) / double(n)),
                                    plan.most_pairs);
    // Neighbours per atom: of the full list's pairs (a subset's share over its query atoms).
    const double neighbours =
        plan.estimated_pairs / double(query_atoms) * (options.half && !subset ? 2.0 : 1.0);
    // Cells of half a cutoff pay only in the dense backend's range kernel (a uniform cutoff, no
    // query); every other search keeps cells of a whole cutoff.
    const bool fused = !subset && options.radii.empty() && options.species_cutoffs.empty();
    const auto backend_for = [&](double cells_per_cutoff) {
        return options.backend == SearchBackend::automatic
                   ? automatic_backend(frame, wrapped.fractional, wrapped.lower, wrapped.upper,
                                       search_radius, cells_per_cutoff, options)
                   : options.backend;
    };
    plan.cells_per_cutoff = options.cells_per_cutoff != 0 ? options.cells_per_cutoff
                            : fused                       ? grid_cells_per_cutoff(neighbours)
                                                          : 1.0;
    // A full list with one cutoff and no query, in the search's order, comes from the half
    // stencil: turning a found pair around costs its stores, finding it again costs a search.
    // Not with offsets (grouped, sorted or ranked): grouping would move the turned pairs one by
    // one.
    plan.mirrored = fused && !options.half && !options.with_offsets();
    plan.backend = backend_for(plan.cells_per_cutoff);
    if (options.cells_per_cutoff == 0 && plan.cells_per_cutoff != 1 &&
        plan.backend != SearchBackend::dense) {
        plan.cells_per_cutoff = 1;
        plan.backend = backend_for(1);
    }
    return plan;
}

ComputePlan plan_compute(const NeighborOptions& options, const ComputeInput& input,
                         const ListLimits& limits) {
    const std::size_t units = input.occupancy.atoms.size();
    ComputePlan plan;
    plan.threads = compute_threads(options, input.estimated_pairs, units);
    // Expected pairs of each unit, from its occupancy; a subset search keeps the query's share
    // of them, for both halves of a full scan.
    const double sphere = sphere_volume(input.max_cutoff);
    const bool subset = input.query_atoms != 0;
    const double share =
        subset ? double(input.query_atoms) / double(input.atoms) : (options.half ? 0.5 : 1.0);
    PairArray<double> expected(units);
    double total = 0;
    for (std::size_t u = 0; u < units; ++u) {
        expected[u] = share * expected_pairs(input.occupancy.atoms[u],
                                             input.occupancy.volume[u] * input.box_volume, sphere);
        total += expected[u];
    }
    if (!(total <= input.most_pairs)) { // also when the occupancy gives no estimate (NaN)
        total = input.most_pairs;
    }
    plan.room = pair_room(total, limits.pairs() == 0 ? 0 : limits.pairs() + input.claim);
    if (plan.threads > 1) {
        PairArray<double> work(units);
        const double neighbours = input.neighbours();
        for (std::size_t u = 0; u < units; ++u) {
            work[u] = occupancy_work(input.occupancy.atoms[u], neighbours);
        }
        plan.batches = plan_batches(work, expected, plan.threads, input.most_pairs);
    }
    return plan;
}

double structure_cost(const Box& box, std::size_t atoms, const NeighborOptions& options) {
    // Measured on small cells: a call costs about 300 stored pairs, an atom's binning about 3.
    constexpr double per_call = 300, per_atom = 3;
    const double n = double(atoms);
    const double sphere = sphere_volume(options.cutoff);
    const double pairs = std::min(expected_pairs(n, std::abs(box.volume()), sphere), n * n * 1e3);
    return per_call + per_atom * n + (options.half ? 0.5 : 1.0) * pairs;
}

std::vector<std::size_t> plan_structure_runs(const std::vector<double>& cost,
                                             const NeighborOptions& options) {
    std::size_t threads = options.threads > 0 ? std::size_t(options.threads) : hardware_threads();
    threads = std::max<std::size_t>(1, std::min(threads, cost.size()));
    return split_work(cost, threads);
}

} // namespace tricell::detail
