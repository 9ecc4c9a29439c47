// Differential libFuzzer harness for the neighbour search: the input bytes choose a box, a few
// positions, a cutoff and the options; search backends compute the list (one of them per input,
// every one on a sample of the inputs; see plan_engines()), and each result is compared with the
// brute-force oracle (tests/support/brute_force.hpp).
//
// The bytes are read through FuzzedDataProvider as a small program of choices, each drawn from
// the cases the contract singles out: boxes that are skewed (tilts of several box lengths),
// nearly flat, left-handed, rotated, or given as raw numbers, with any periodicity; positions at
// fractional 0, -0 and 1, on cell faces, coincident, shifted by whole lattice vectors, far
// outside the box or raw; cutoffs that are tiny, exactly a pair's distance (a shell), larger
// than the box, or raw (0, negative, huge). Options: half, sorted, threads, cells per cutoff,
// cell reduction, max_cells, hash table size, octree leaf size.
//
// A rejected input must throw tricell::Error with a one-line message, the same for every
// backend.
// An accepted one must give the oracle's pairs. Pairs whose distance is within rounding of the
// cutoff may be in or out (the search subtracts wrapped positions, the oracle the caller's); the
// rounding allowance grows with the condition number of the box and the size of the
// coordinates. The oracle runs only when its work is small, so that each input stays fast.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include <fuzzer/FuzzedDataProvider.h>

#include <tricell/box.hpp>
#include <tricell/error.hpp>
#include <tricell/neighbor_list.hpp>

#include "differential.hpp"
#include "support/brute_force.hpp"

namespace {

using tricell::Box;
using tricell::NeighborList;
using tricell::NeighborOptions;
using tricell::fuzz::broken;
using tricell::fuzz::check_message;
using tricell::testing::PairKey;

constexpr std::size_t max_atoms = 8;
constexpr std::size_t max_pairs =
    4000; // larger lists are refused: their maps cost seconds per input
constexpr double max_oracle_work = 2e5; // pair-image tests

double pick(FuzzedDataProvider& in, std::initializer_list<double> values) {
    const std::size_t k = in.ConsumeIntegralInRange<std::size_t>(0, values.size() - 1);
    return *(values.begin() + static_cast<std::ptrdiff_t>(k));
}

// A real number: a usual one, an extreme one, or any double the bytes spell.
double real(FuzzedDataProvider& in) {
    switch (in.ConsumeIntegralInRange(0, 3)) {
    case 0:
        return pick(in, {0.0, -0.0, 1.0, -1.0, 0.5, 2.0, 3.0, 1.0 / 3.0, 2.5, 10.0, -4.25});
    case 1:
        return pick(in, {1e-300, 5e-324, 1e-8, 1e8, 1e300, -1e-12, 1e-3, 1e3,
                         std::numeric_limits<double>::quiet_NaN(),
                         std::numeric_limits<double>::infinity()});
    case 2:
        return in.ConsumeFloatingPointInRange(-20.0, 20.0);
    default:
        return in.ConsumeFloatingPoint<double>();
    }
}

// A fractional coordinate singled out by the contract, or a near one.
double fractional(FuzzedDataProvider& in) {
    switch (in.ConsumeIntegralInRange(0, 2)) {
    case 0:
        return pick(in, {0.0, -0.0, 1.0, 0.5, 0.25, -1e-17, 1e-17, 1.0 - 0x1p-53, -0x1p-60,
                         0.999999999999, 2.0, -1.0, 1e3, -1e6, 1e9 + 0.5, 1e9 - 1.0, 3e9});
    case 1:
        return in.ConsumeProbability<double>();
    default:
        return in.ConsumeFloatingPointInRange(-3.0, 4.0);
    }
}

Eigen::Matrix3d matrix(FuzzedDataProvider& in) {
    Eigen::Matrix3d h = Eigen::Matrix3d::Zero();
    if (in.ConsumeIntegralInRange(0, 4) == 0) {
        for (int k = 0; k < 9; ++k) {
            h(k / 3, k % 3) = real(in);
        }
        return h;
    }
    // Upper triangular from three lengths and tilts (in box lengths, up to several: skewed).
    for (int axis = 0; axis < 3; ++axis) {
        h(axis, axis) = in.ConsumeBool() ? pick(in, {1.0, 2.0, 3.0, 5.0, 0.7, 10.0})
                                         : in.ConsumeFloatingPointInRange(0.1, 12.0);
    }
    for (const auto& [row, col] : {std::pair{0, 1}, std::pair{0, 2}, std::pair{1, 2}}) {
        if (in.ConsumeBool()) {
            const double tilt = in.ConsumeBool() ? double(in.ConsumeIntegralInRange(-6, 6)) / 2
                                                 : in.ConsumeFloatingPointInRange(-8.0, 8.0);
            h(row, col) = tilt * h(row, row);
        }
    }
    switch (in.ConsumeIntegralInRange(0, 4)) {
    case 1: // nearly flat: c close to the plane of a and b
        h.col(2) = in.ConsumeFloatingPointInRange(-2.0, 2.0) * h.col(0) +
                   in.ConsumeFloatingPointInRange(-2.0, 2.0) * h.col(1) +
                   pick(in, {1e-3, 1e-5, 1e-7, 1e-9, 1e-12}) * Eigen::Vector3d(0, 0, h(2, 2));
        break;
    case 2: // left-handed
        h.col(in.ConsumeIntegralInRange(0, 2)) *= -1;
        break;
    case 3: { // rotated: no longer triangular
        const double t = in.ConsumeFloatingPointInRange(0.0, 6.3);
        Eigen::Matrix3d r;
        r << std::cos(t), -std::sin(t), 0, std::sin(t), std::cos(t), 0, 0, 0, 1;
        Eigen::Matrix3d q;
        q << 1, 0, 0, 0, std::cos(2 * t), -std::sin(2 * t), 0, std::sin(2 * t), std::cos(2 * t);
        h = q * r * h;
        break;
    }
    default:
        break;
    }
    return h;
}

std::vector<Eigen::Vector3d> positions(FuzzedDataProvider& in, const Box& box) {
    const std::size_t n = in.ConsumeIntegralInRange<std::size_t>(0, max_atoms);
    std::vector<Eigen::Vector3d> x;
    for (std::size_t i = 0; i < n; ++i) {
        Eigen::Vector3d s;
        switch (in.ConsumeIntegralInRange(0, 4)) {
        case 0: // coincident with an earlier atom
            if (!x.empty()) {
                x.push_back(x[in.ConsumeIntegralInRange<std::size_t>(0, x.size() - 1)]);
                continue;
            }
            [[fallthrough]];
        case 1: // an earlier atom moved by whole lattice vectors
            if (!x.empty()) {
                const Eigen::Vector3d k(in.ConsumeIntegralInRange(-3, 3),
                                        in.ConsumeIntegralInRange(-3, 3),
                                        in.ConsumeIntegralInRange(-3, 3));
                x.push_back(x[in.ConsumeIntegralInRange<std::size_t>(0, x.size() - 1)] +
                            box.matrix() * k);
                continue;
            }
            [[fallthrough]];
        case 2: // on a face of the box
            s = Eigen::Vector3d(in.ConsumeProbability<double>(), in.ConsumeProbability<double>(),
                                in.ConsumeProbability<double>());
            s[in.ConsumeIntegralInRange(0, 2)] = pick(in, {0.0, -0.0, 1.0});
            break;
        case 3: // Cartesian, raw
            x.emplace_back(real(in), real(in), real(in));
            continue;
        default:
            s = Eigen::Vector3d(fractional(in), fractional(in), fractional(in));
            break;
        }
        x.push_back(box.matrix() * s);
    }
    return x;
}

double cutoff(FuzzedDataProvider& in, const Box& box, const std::vector<Eigen::Vector3d>& x) {
    const double widest = box.perpendicular_widths().maxCoeff();
    switch (in.ConsumeIntegralInRange(0, 4)) {
    case 0:
        return pick(in, {1e-300, 5e-324, 1e-12, 1e-6});
    case 1: { // exactly the distance of one pair (i, j, S): a shell
        if (x.empty()) {
            return 1;
        }
        const std::size_t i = in.ConsumeIntegralInRange<std::size_t>(0, x.size() - 1);
        const std::size_t j = in.ConsumeIntegralInRange<std::size_t>(0, x.size() - 1);
        const Eigen::Vector3d s(in.ConsumeIntegralInRange(-2, 2), in.ConsumeIntegralInRange(-2, 2),
                                in.ConsumeIntegralInRange(-2, 2));
        return (x[j] - x[i] + box.matrix() * s).norm();
    }
    case 2: // larger than the box
        return widest * pick(in, {1.0, 1.5, 2.0, 3.0, 4.5});
    case 3:
        return box.perpendicular_widths().minCoeff() * in.ConsumeFloatingPointInRange(0.01, 1.2);
    default:
        return real(in);
    }
}

} // namespace

// Which engines an input runs, chosen by a hash of its bytes (so a replay checks the same, and
// the decoding of the bytes is untouched). One input in `all_every` runs every engine of the
// registry, each with the drawn thread count (its list compared with one thread's) and with the
// for_each_pair walk. Every other input runs one engine on one thread, with the drawn threads and
// the walk on one in `costly_every` of them. So each of the six engines meets the oracle on about
// 22 % of the inputs and gets the walk on about 10 %. A search and the harness's check of it cost
// far more than the oracle at these sizes, so fewer engines per input mean more inputs a second:
// a second engine on every input (each engine checked on 37 % of the inputs) gave 0.7 times as
// many, every engine on every input a fifth as many.
constexpr std::uint32_t all_every = 16;
constexpr std::uint32_t costly_every = 4;

struct EnginePlan {
    std::vector<std::size_t> engines; // indices into search_backends(), in run order
    std::size_t costly = 0;           // the first `costly` get the threads and the walk
};

EnginePlan plan_engines(std::uint32_t hash, std::size_t count) {
    EnginePlan plan;
    if (hash % all_every == 0 || count < 2 || tricell::fuzz::every_check()) {
        for (std::size_t b = 0; b < count; ++b) {
            plan.engines.push_back(b);
        }
        plan.costly = count;
        return plan;
    }
    const std::uint32_t rest = hash / all_every;
    plan.engines = {rest % count};
    plan.costly = (rest / count) % costly_every == 0 ? 1 : 0;
    return plan;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::uint32_t hash = tricell::fuzz::input_hash(data, size);
    FuzzedDataProvider in(data, size);
    tricell::Periodicity pbc;
    for (bool& axis : pbc.axes) {
        axis = in.ConsumeBool();
    }
    const Eigen::Matrix3d h = matrix(in);
    std::optional<Box> made;
    try {
        made = Box::from_columns(h, pbc);
    } catch (const tricell::Error& e) {
        check_message(e.what());
        return 0;
    }
    const Box& box = *made;
    const std::vector<Eigen::Vector3d> x = positions(in, box);

    NeighborOptions options;
    options.cutoff = cutoff(in, box, x);
    options.half = in.ConsumeBool();
    const int order = in.ConsumeIntegralInRange(0, 3); // bit 0 is what ConsumeBool() reads
    options.sorted = (order & 1) != 0;
    options.grouped = order == 2;
    options.threads = int(pick(in, {1, 1, 2, 3, 0}));
    options.cells_per_cutoff = pick(in, {1, 1, 2, 3, 1.5});
    options.reduce_cell = in.ConsumeBool();
    options.max_cells = std::size_t(pick(in, {0, 0, 1, 7, 64}));
    options.hash_table_size = std::size_t(pick(in, {0, 0, 1, 3}));
    options.leaf_size = std::size_t(pick(in, {0, 0, 1, 2, 5}));
    options.max_pairs = max_pairs;
    options.quantities.shifts = options.quantities.distances = options.quantities.vectors = true;

    if (tricell::fuzz::too_many_images(box, options.cutoff, x.size())) {
        return 0; // speed (differential.hpp)
    }
    if (std::getenv("TRICELL_FUZZ_VERBOSE") != nullptr) {
        // For reading a crash: TRICELL_FUZZ_VERBOSE=1 search_fuzzer crash-...
        std::fprintf(stderr, "pbc %d %d %d\nH (columns a, b, c) =\n", pbc[0], pbc[1], pbc[2]);
        for (int row = 0; row < 3; ++row) {
            std::fprintf(stderr, "  %.17g %.17g %.17g\n", h(row, 0), h(row, 1), h(row, 2));
        }
        for (const Eigen::Vector3d& r : x) {
            std::fprintf(stderr, "x %.17g %.17g %.17g\n", r[0], r[1], r[2]);
        }
        std::fprintf(stderr,
                     "cutoff %.17g half %d sorted %d grouped %d threads %d cells_per_cutoff %g "
                     "reduce_cell %d max_cells %zu hash_table_size %zu leaf_size %zu\n",
                     options.cutoff, options.half, options.sorted, options.grouped, options.threads,
                     options.cells_per_cutoff, options.reduce_cell, options.max_cells,
                     options.hash_table_size, options.leaf_size);
    }
    const bool have_oracle =
        tricell::fuzz::oracle_affordable(box, x, options.cutoff, max_oracle_work);
    const auto cutoff_of = [&](std::uint32_t, std::uint32_t) { return options.cutoff; };
    static tricell::fuzz::PairRows expected;
    expected.clear();
    if (have_oracle) {
        tricell::fuzz::oracle_rows(box, x, options.cutoff, cutoff_of, options.half, expected);
    }

    int rejected = -1; // unknown until the first engine ran
    std::string first_message;
    const auto& backends = tricell::search_backends();
    EnginePlan plan = plan_engines(hash, backends.size());
    const int drawn_threads = options.threads;
    // One list and one search object for every engine and input: their buffers are reused.
    static NeighborList list;
    static tricell::NeighborSearch walker;
    static tricell::fuzz::PairRows found;
    for (std::size_t k = 0; k < plan.engines.size(); ++k) {
        const tricell::SearchBackend backend = backends[plan.engines[k]];
        const bool costly = k < plan.costly;
        options.backend = backend;
        options.threads = costly ? drawn_threads : 1;
        const char* engine = tricell::backend_name(backend);
        bool threw = false;
        std::string message;
        try {
            tricell::compute_neighbors(box, x, options, list);
        } catch (const tricell::Error& e) {
            check_message(e.what());
            threw = true;
            message = e.what();
            if (rejected < 0) {
                first_message = e.what();
            }
        }
        if (rejected >= 0 && int(threw) != rejected) {
            broken(std::string("engines disagree on rejecting the input: ") + engine +
                   (threw ? " threw: " + message
                          : " did not throw; the first threw: " + first_message));
        }
        rejected = int(threw);
        if (threw) {
            // A refusal is cheap: every other engine must refuse the same input too.
            if (k == 0 && plan.engines.size() < backends.size()) {
                for (std::size_t b = 0; b < backends.size(); ++b) {
                    if (b != plan.engines[0]) {
                        plan.engines.push_back(b);
                    }
                }
            }
            continue;
        }
        if (!list.empty() && !have_oracle && x.empty()) {
            broken("pairs without atoms");
        }
        tricell::fuzz::check_rules(box, x.size(), options.half,
                                   options.sorted    ? tricell::fuzz::Order::sorted
                                   : options.grouped ? tricell::fuzz::Order::grouped
                                                     : tricell::fuzz::Order::any,
                                   max_pairs, tricell::fuzz::view(list));
        if (options.threads != 1) {
            // The stored list is the same pair for pair whatever the number of threads.
            NeighborOptions single = options;
            single.threads = 1;
            const NeighborList one = tricell::compute_neighbors(box, x, single);
            if (one.i() != list.i() || one.j() != list.j() || one.shifts() != list.shifts() ||
                one.distances() != list.distances() || one.vectors() != list.vectors()) {
                broken(std::string(engine) + ": threaded list differs from one thread");
            }
        }
        if (have_oracle) {
            tricell::fuzz::rows_of(list, engine, found);
            tricell::fuzz::compare(box, x, cutoff_of, expected, found, engine);
        }
        if (have_oracle && costly) {
            found.clear();
            walker.build(box, x, options);
            walker.for_each_pair([&](const tricell::Pair& p) {
                found.emplace_back(PairKey{p.i, p.j, p.shift[0], p.shift[1], p.shift[2]},
                                   tricell::testing::PairValue{p.distance(), p.vector});
            });
            tricell::fuzz::sort_rows(found, engine);
            tricell::fuzz::compare(box, x, cutoff_of, expected, found, engine);
        }
    }
    return 0;
}
