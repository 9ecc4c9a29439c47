// libFuzzer harness for the C API (include/tricell.h): the input bytes are a program of choices
// (FuzzedDataProvider), a few calls in a row on one search handle, one list handle and one
// Verlet handle, with hostile arguments: NULL pointers, flags other than 0 and 1, unknown
// backends, NaN, infinite, huge and denormal cutoffs and positions, flat boxes and zero vectors
// on periodic axes, radii and species tables with bad entries, n = 0 and n too large, tiny
// max_pairs, a Verlet list updated with a changing atom count or periodicity, and the list
// handle reused across calls (so a failed call must empty what the last one stored).
//
// What it checks are the promises of CONTRACT section 4 and tricell.h: every call returns one of
// the five statuses; TRICELL_OK comes with the message "" and any other status with a one-line
// message (and never TRICELL_ERROR_INTERNAL or OUT_OF_MEMORY, which would mean a bug or a large
// allocation from a small input); a failed box constructor leaves its output untouched and a
// failed search leaves the list empty; tricell_neighbors() agrees with the C++ API called with
// the same arguments (the same status class, message and arrays) and, when the brute-force
// oracle is affordable, with the oracle (through differential.hpp: the list rules and the pairs
// up to rounding at the cutoff, for one cutoff, radii or a species table); a Verlet update agrees
// with the oracle at r_c. Every array is allocated at exactly the length the call may read, so
// AddressSanitizer reports any access outside it.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <fuzzer/FuzzedDataProvider.h>

#include <tricell/box.hpp>
#include <tricell/error.hpp>
#include <tricell/neighbor_list.hpp>

#include "differential.hpp"
#include "support/brute_force.hpp"
#include "tricell.h"

namespace {

using tricell::fuzz::broken;
using tricell::testing::PairKey;

constexpr std::size_t max_atoms = 8;
constexpr double max_oracle_work = 2e5; // pair-image tests
// max_pairs in place of the default 5e8, with which a cutoff of a hundred box widths would be
// allowed to run for minutes. max_pairs = 0 (no limit) is not tried: the search then reserves
// room for the pairs its occupancy estimate predicts (up to 2^24 per chunk), and one atom near
// a thin open axis predicted that many; filling the untouched reservation is free in an
// optimised build but took 4 s in this instrumented one (a campaign timeout). 4 000 rather than
// more: every pair is checked five ways (the rules, the oracle's rows, the sorted comparison, the
// C++ arrays, the C copy), and inputs with thousands of pairs were half of a campaign corpus's
// time; a list that would pass the limit is refused, and that refusal is checked instead. Large
// lists belong to the random campaign (tests/property/random_campaign_test.cpp).
constexpr std::size_t bounded_pairs = 4000;

template <class T> T pick(FuzzedDataProvider& in, std::initializer_list<T> values) {
    const std::size_t k = in.ConsumeIntegralInRange<std::size_t>(0, values.size() - 1);
    return *(values.begin() + static_cast<std::ptrdiff_t>(k));
}

// A real number: a usual one, an extreme one, or any double the bytes spell.
double real(FuzzedDataProvider& in) {
    switch (in.ConsumeIntegralInRange(0, 3)) {
    case 0:
        return pick(in, {0.0, -0.0, 1.0, -1.0, 0.5, 2.0, 3.0, 2.5, 10.0, -4.25});
    case 1:
        return pick(in, {1e-300, 5e-324, 1e-8, 1e8, 1e300, -1e-12, 1e-3, 1e3,
                         std::numeric_limits<double>::quiet_NaN(),
                         std::numeric_limits<double>::infinity(),
                         -std::numeric_limits<double>::infinity()});
    case 2:
        return in.ConsumeFloatingPointInRange(-12.0, 12.0);
    default:
        return in.ConsumeFloatingPoint<double>();
    }
}

// A flag: mostly 0 or 1, sometimes a value the API must refuse.
int flag(FuzzedDataProvider& in) {
    return in.ConsumeIntegralInRange(0, 7) == 0 ? pick(in, {2, -1, 255, 1 << 30})
                                                : in.ConsumeBool();
}

// options.sorted and options.grouped from the bytes flag() reads for one flag (so a corpus
// input means what it meant before grouped existed): a bad value goes to one of the two, and
// an even second byte with bit 1 set asks for grouped.
void order_flags(FuzzedDataProvider& in, tricell_neighbor_options& o) {
    o.sorted = o.grouped = 0;
    if (in.ConsumeIntegralInRange(0, 7) == 0) {
        const int bad = pick(in, {2, -1, 255, 1 << 30});
        (bad == 2 || bad == 255 ? o.sorted : o.grouped) = bad;
        return;
    }
    const int order = in.ConsumeIntegralInRange(0, 3); // bit 0 is what ConsumeBool() reads
    o.sorted = order & 1;
    o.grouped = order == 2 ? 1 : 0;
}

// The status promise of every call; returns whether it succeeded.
bool check_status(tricell_status status, const char* call) {
    const char* message = tricell_last_error();
    if (message == nullptr) {
        broken(std::string(call) + ": tricell_last_error() is NULL");
    }
    const std::string text = message;
    if (status == TRICELL_OK) {
        if (!text.empty()) {
            broken(std::string(call) + ": TRICELL_OK with the message " + text);
        }
        return true;
    }
    if (status != TRICELL_ERROR_INVALID_ARGUMENT && status != TRICELL_ERROR_GEOMETRY) {
        broken(std::string(call) + ": status " + std::to_string(int(status)) + ": " + text);
    }
    if (text.size() > 1023) {
        broken(std::string(call) + ": message longer than 1023 bytes");
    }
    tricell::fuzz::check_message(text);
    return false;
}

// A call with a NULL where a handle or output belongs must fail with a message.
void expect_refused(tricell_status status, const char* call) {
    if (check_status(status, call)) {
        broken(std::string(call) + " accepted a NULL pointer");
    }
}

// What the harness carries from one call to the next.
struct State {
    tricell_neighbor_search* search = nullptr;
    tricell_neighbor_list* list = nullptr;
    tricell_verlet* verlet = nullptr;
    tricell_verlet_options verlet_options{};
    // The last box a constructor made (or a default cube), for later calls.
    tricell_box box{{{3, 0, 0}, {0, 3, 0}, {0, 0, 3}}, {1, 1, 1}};
    ~State() {
        tricell_neighbor_search_destroy(search);
        tricell_neighbor_list_destroy(list);
        tricell_verlet_destroy(verlet);
    }
};

// Box vectors as rows: a cube, a skewed or flat or left-handed box, a zero vector, or raw.
std::vector<double> rows(FuzzedDataProvider& in) {
    std::vector<double> m = {3, 0, 0, 0, 3, 0, 0, 0, 3};
    switch (in.ConsumeIntegralInRange(0, 5)) {
    case 0: // skewed: tilts of several box lengths
        for (int k : {3, 6, 7}) {
            m[std::size_t(k)] = in.ConsumeFloatingPointInRange(-8.0, 8.0);
        }
        break;
    case 1: // nearly flat: c almost in the plane of a and b
        m[6] = in.ConsumeFloatingPointInRange(-3.0, 3.0);
        m[8] = pick(in, {1e-3, 1e-9, 1e-14, 5e-324, 0.0});
        break;
    case 2: // a zero vector
        std::fill_n(m.begin() + 3 * in.ConsumeIntegralInRange(0, 2), 3, 0.0);
        break;
    case 3: // left-handed
        m[0] = -m[0];
        break;
    case 4:
        for (double& v : m) {
            v = real(in);
        }
        break;
    default:
        for (int k = 0; k < 3; ++k) {
            m[std::size_t(4 * k)] = in.ConsumeFloatingPointInRange(0.2, 10.0);
        }
        break;
    }
    return m;
}

// One of the three box constructors, maybe with NULL arguments or bad flags. On failure the
// output must keep its bytes; on success it holds the vectors as given and the flags.
void make_box(FuzzedDataProvider& in, State& state) {
    const std::vector<double> m = rows(in);
    const int periodic[3] = {flag(in), flag(in), flag(in)};
    const int kind = in.ConsumeIntegralInRange(0, 2);
    const bool null_matrix = in.ConsumeIntegralInRange(0, 15) == 0;
    const bool null_flags = in.ConsumeIntegralInRange(0, 15) == 0;
    const bool null_box = in.ConsumeIntegralInRange(0, 15) == 0;
    tricell_box out;
    std::memset(&out, 0xA5, sizeof out);
    tricell_box before = out;
    tricell_status status;
    if (kind == 0) {
        status = tricell_box_from_rows(null_matrix ? nullptr : m.data(),
                                       null_flags ? nullptr : periodic, null_box ? nullptr : &out);
    } else if (kind == 1) {
        status =
            tricell_box_from_columns(null_matrix ? nullptr : m.data(),
                                     null_flags ? nullptr : periodic, null_box ? nullptr : &out);
    } else {
        const double a = in.ConsumeBool() ? real(in) : 3.0, b = in.ConsumeBool() ? real(in) : 4.0,
                     c = in.ConsumeBool() ? real(in) : 5.0;
        const double alpha = in.ConsumeBool() ? real(in) * 60 : 90.0,
                     beta = in.ConsumeBool() ? real(in) * 60 : 80.0,
                     gamma = in.ConsumeBool() ? real(in) * 60 : 120.0;
        status =
            tricell_box_from_parameters(a, b, c, alpha, beta, gamma,
                                        null_flags ? nullptr : periodic, null_box ? nullptr : &out);
    }
    if (!check_status(status, "tricell_box_from_*")) {
        if (std::memcmp(&out, &before, sizeof out) != 0) {
            broken("a failed box constructor wrote its output");
        }
        return;
    }
    if ((null_matrix && kind < 2) || null_flags || null_box) {
        broken("a box constructor accepted a NULL pointer");
    }
    for (int k = 0; k < 3; ++k) {
        if (out.periodic[k] != periodic[k]) {
            broken("a box constructor changed the periodicity");
        }
        // The vectors of open axes may be completed (docs/c-fortran.md); periodic ones never.
        for (int c = 0; c < 3 && kind < 2 && periodic[k] != 0; ++c) {
            const double given = kind == 0 ? m[std::size_t(3 * k + c)] : m[std::size_t(3 * c + k)];
            if (!(out.vectors[k][c] == given)) {
                broken("a box constructor changed a periodic lattice vector");
            }
        }
    }
    state.box = out;
}

// The C++ box of a C box, if the C++ API accepts it.
std::optional<tricell::Box> cxx_box(const tricell_box& box) {
    Eigen::Matrix3d h;
    tricell::Periodicity pbc;
    for (int k = 0; k < 3; ++k) {
        for (int c = 0; c < 3; ++c) {
            h(c, k) = box.vectors[k][c];
        }
        if (box.periodic[k] != 0 && box.periodic[k] != 1) {
            return std::nullopt;
        }
        pbc.axes[std::size_t(k)] = box.periodic[k] == 1;
    }
    try {
        return tricell::Box::from_columns(h, pbc);
    } catch (const tricell::Error&) {
        return std::nullopt;
    }
}

// The box of a call: the last one made, that one with its flags or a vector spoiled, or NULL.
const tricell_box* call_box(FuzzedDataProvider& in, State& state, tricell_box& scratch) {
    scratch = state.box;
    switch (in.ConsumeIntegralInRange(0, 7)) {
    case 0:
        return nullptr;
    case 1:
        scratch.periodic[in.ConsumeIntegralInRange(0, 2)] = pick(in, {2, -1, 7});
        break;
    case 2:
        scratch.vectors[in.ConsumeIntegralInRange(0, 2)][in.ConsumeIntegralInRange(0, 2)] =
            real(in);
        break;
    case 3:
        scratch.periodic[in.ConsumeIntegralInRange(0, 2)] ^= 1;
        break;
    default:
        break;
    }
    return &scratch;
}

// Positions: mostly in or near the box, some coincident, some raw (NaN, huge, denormal).
std::vector<Eigen::Vector3d> positions(FuzzedDataProvider& in, const tricell_box& box,
                                       std::size_t n) {
    std::vector<Eigen::Vector3d> x;
    for (std::size_t i = 0; i < n; ++i) {
        switch (in.ConsumeIntegralInRange(0, 5)) {
        case 0:
            if (!x.empty()) {
                x.push_back(x[in.ConsumeIntegralInRange<std::size_t>(0, x.size() - 1)]);
                break;
            }
            [[fallthrough]];
        case 1:
            x.emplace_back(real(in), real(in), real(in));
            break;
        default: {
            Eigen::Vector3d r = Eigen::Vector3d::Zero();
            for (int k = 0; k < 3; ++k) {
                const double s = in.ConsumeFloatingPointInRange(-1.5, 2.5);
                for (int c = 0; c < 3; ++c) {
                    r[c] += s * box.vectors[k][c];
                }
            }
            x.push_back(r);
            break;
        }
        }
    }
    return x;
}

// The variable-cutoff arrays of one call (kept alive for it).
struct Tables {
    std::vector<double> radii;
    std::vector<std::int32_t> species;
    std::vector<tricell_species_cutoff> cutoffs;
};

double positive(FuzzedDataProvider& in) {
    return in.ConsumeIntegralInRange(0, 5) == 0 ? real(in)
                                                : in.ConsumeFloatingPointInRange(0.0, 4.0);
}

// Whether this input's calls keep a valid thread count above one, chosen by a hash of the input's
// bytes (so a replay checks the same, and the decoding is untouched): one input in
// `threaded_every`. On the others such a count becomes 1. A threaded call starts its helper
// threads (AddressSanitizer maps state for each) and fills its list through the ordered batches,
// which together cost more than the rest of the input, and the threaded list is checked with
// the same rules and against the same oracle on the sampled inputs; the refused counts (-1, 5000)
// are always passed as drawn.
constexpr std::uint32_t threaded_every = 8;
bool threaded_input = true;

// Whether this input's successful tricell_neighbors calls are searched again through the C++ API
// and compared array for array (one input in `compared_every`, by other bits of the same hash;
// every refusal is compared). The second search was a third of the input's time; the C list is
// checked against the rules and the oracle on every input.
constexpr std::uint32_t compared_every = 4;
bool compared_input = true;

tricell_neighbor_options neighbor_options(FuzzedDataProvider& in, std::size_t n, Tables& tables) {
    tricell_neighbor_options o;
    if (!check_status(tricell_neighbor_options_init(&o), "tricell_neighbor_options_init")) {
        broken("tricell_neighbor_options_init failed");
    }
    o.cutoff = in.ConsumeIntegralInRange(0, 3) == 0
                   ? real(in)
                   : pick(in, {1e-300, 5e-324, 0.5, 1.0, 2.0, 3.0, 4.5, 6.0});
    if (in.ConsumeBool()) {
        o.cutoff = in.ConsumeFloatingPointInRange(0.0, 7.0);
    }
    o.half = flag(in);
    order_flags(in, o);
    o.shifts = in.ConsumeIntegralInRange(0, 3) == 0 ? flag(in) : 1;
    o.distances = in.ConsumeIntegralInRange(0, 3) == 0 ? flag(in) : 1;
    o.vectors = flag(in);
    o.threads = pick(in, {1, 1, 1, 2, 3, 0, -1, 5000});
    if (!threaded_input && (o.threads == 2 || o.threads == 3)) {
        o.threads = 1;
    }
    o.backend = pick(in, {0, 0, 1, 2, 3, 4, 5, 6, -1, 99});
    o.max_pairs = pick<std::size_t>(in, {bounded_pairs, bounded_pairs, 1, 2, 5, 100});
    switch (in.ConsumeIntegralInRange(0, 5)) {
    case 0: // radii, usually with cutoff 0
        tables.radii.resize(n);
        for (double& r : tables.radii) {
            r = positive(in);
        }
        o.radii = tables.radii.data();
        o.cutoff = in.ConsumeIntegralInRange(0, 4) == 0 ? o.cutoff : 0.0;
        break;
    case 1: { // species and a table, usually with cutoff 0
        tables.species.resize(n);
        for (std::int32_t& s : tables.species) {
            s = in.ConsumeIntegralInRange(0, 5) == 0 ? in.ConsumeIntegral<std::int32_t>()
                                                     : in.ConsumeIntegralInRange(-1, 2);
        }
        tables.cutoffs.resize(in.ConsumeIntegralInRange<std::size_t>(0, 5));
        for (tricell_species_cutoff& e : tables.cutoffs) {
            e.a = in.ConsumeIntegralInRange(-1, 2);
            e.b = in.ConsumeIntegralInRange(-1, 2);
            e.cutoff = positive(in);
        }
        if (in.ConsumeIntegralInRange(0, 7) != 0) {
            o.species = tables.species.data();
        }
        o.species_cutoffs = tables.cutoffs.empty() || in.ConsumeIntegralInRange(0, 9) == 0
                                ? nullptr
                                : tables.cutoffs.data();
        o.species_cutoff_count = tables.cutoffs.size();
        o.cutoff = in.ConsumeIntegralInRange(0, 4) == 0 ? o.cutoff : 0.0;
        break;
    }
    default:
        break;
    }
    return o;
}

// For reading a crash: TRICELL_FUZZ_VERBOSE=1 c_api_fuzzer crash-... prints each search call.
const bool verbose = std::getenv("TRICELL_FUZZ_VERBOSE") != nullptr;

void print_call(const tricell_box& box, const std::vector<Eigen::Vector3d>& x,
                const tricell_neighbor_options& o) {
    std::fprintf(stderr, "box periodic %d %d %d, rows\n", box.periodic[0], box.periodic[1],
                 box.periodic[2]);
    for (const auto& row : box.vectors) {
        std::fprintf(stderr, "  %.17g %.17g %.17g\n", row[0], row[1], row[2]);
    }
    for (const Eigen::Vector3d& r : x) {
        std::fprintf(stderr, "x %.17g %.17g %.17g\n", r[0], r[1], r[2]);
    }
    std::fprintf(stderr,
                 "cutoff %.17g half %d sorted %d grouped %d shifts %d distances %d vectors %d "
                 "threads %d backend %d max_pairs %zu radii %s species %s table %zu\n",
                 o.cutoff, o.half, o.sorted, o.grouped, o.shifts, o.distances, o.vectors, o.threads,
                 o.backend, o.max_pairs, o.radii ? "set" : "NULL", o.species ? "set" : "NULL",
                 o.species_cutoff_count);
    for (std::size_t i = 0; o.radii != nullptr && i < x.size(); ++i) {
        std::fprintf(stderr, "radius %.17g\n", o.radii[i]);
    }
    for (std::size_t k = 0; o.species_cutoffs != nullptr && k < o.species_cutoff_count; ++k) {
        std::fprintf(stderr, "table %d %d %.17g\n", o.species_cutoffs[k].a, o.species_cutoffs[k].b,
                     o.species_cutoffs[k].cutoff);
    }
}

// The largest cutoff any pair can have (NaN passes through, so the oracle is skipped).
double largest_cutoff(const tricell_neighbor_options& o, std::size_t n) {
    if (o.radii != nullptr && n > 0) {
        double r = 0;
        for (std::size_t i = 0; i < n; ++i) {
            r = std::isnan(o.radii[i]) ? o.radii[i] : std::max(r, o.radii[i]);
        }
        return 2 * r;
    }
    if (o.species_cutoffs != nullptr && o.species_cutoff_count > 0) {
        double c = 0;
        for (std::size_t k = 0; k < o.species_cutoff_count; ++k) {
            const double e = o.species_cutoffs[k].cutoff;
            c = std::isnan(e) ? e : std::max(c, e);
        }
        return c;
    }
    return o.cutoff;
}

// The same options for the C++ API, copied field by field as a C caller means them.
std::optional<tricell::NeighborOptions> cxx_options(const tricell_neighbor_options& o,
                                                    std::size_t n) {
    for (const int f : {o.half, o.sorted, o.grouped, o.shifts, o.distances, o.vectors}) {
        if (f != 0 && f != 1) {
            return std::nullopt;
        }
    }
    if (o.species_cutoff_count > 0 && o.species_cutoffs == nullptr) {
        return std::nullopt;
    }
    tricell::NeighborOptions c;
    c.cutoff = o.cutoff;
    c.half = o.half == 1;
    c.sorted = o.sorted == 1;
    c.grouped = o.grouped == 1;
    c.quantities = tricell::Quantities{o.shifts == 1, o.distances == 1, o.vectors == 1};
    c.threads = o.threads;
    c.backend = static_cast<tricell::SearchBackend>(o.backend);
    c.max_pairs = o.max_pairs;
    if (o.radii != nullptr) {
        c.radii.assign(o.radii, o.radii + n);
    }
    if (o.species != nullptr) {
        c.species.assign(o.species, o.species + n);
    }
    for (std::size_t k = 0; k < o.species_cutoff_count; ++k) {
        const tricell_species_cutoff& e = o.species_cutoffs[k];
        c.species_cutoffs.push_back(tricell::SpeciesCutoff{e.a, e.b, e.cutoff});
    }
    return c;
}

// A C list view as sorted rows in `out` (cleared first), with the oracle's vector (or distance)
// where it was not stored.
void to_rows(const tricell_pairs& p, const tricell::Box& box, const std::vector<Eigen::Vector3d>& x,
             const char* call, tricell::fuzz::PairRows& out) {
    out.clear();
    out.reserve(p.size);
    for (std::size_t k = 0; k < p.size; ++k) {
        const PairKey key{p.i[k], p.j[k], p.shifts[3 * k], p.shifts[3 * k + 1],
                          p.shifts[3 * k + 2]};
        const Eigen::Vector3d exact =
            x[p.j[k]] - x[p.i[k]] +
            box.matrix() * Eigen::Vector3d(std::get<2>(key), std::get<3>(key), std::get<4>(key));
        const Eigen::Vector3d d =
            p.vectors == nullptr
                ? exact
                : Eigen::Vector3d(p.vectors[3 * k], p.vectors[3 * k + 1], p.vectors[3 * k + 2]);
        out.emplace_back(key, tricell::testing::PairValue{
                                  p.distances != nullptr ? p.distances[k] : exact.norm(), d});
    }
    tricell::fuzz::sort_rows(out, call);
}

// The oracle's rows and a list's rows, buffers kept from input to input.
tricell::fuzz::PairRows expected_rows;
tricell::fuzz::PairRows found_rows;

// `pairs` against the oracle (see tricell::fuzz::compare).
template <class CutoffOf>
void compare_with_oracle(const tricell::Box& box, const std::vector<Eigen::Vector3d>& x,
                         double largest, const CutoffOf& cutoff_of, bool half,
                         const tricell_pairs& pairs, const char* call) {
    tricell::fuzz::oracle_rows(box, x, largest, cutoff_of, half, expected_rows);
    to_rows(pairs, box, x, call, found_rows);
    tricell::fuzz::compare(box, x, cutoff_of, expected_rows, found_rows, call);
}

// The list's view after a failed call: empty.
void expect_empty(const tricell_pairs& p, const char* call) {
    if (p.size != 0) {
        broken(std::string(call) + " failed but left " + std::to_string(p.size) + " pairs");
    }
}

tricell_pairs list_pairs(const tricell_neighbor_list* list) {
    tricell_pairs p;
    if (!check_status(tricell_neighbor_list_pairs(list, &p), "tricell_neighbor_list_pairs")) {
        broken("tricell_neighbor_list_pairs failed on a valid list");
    }
    return p;
}

// The C list equals the C++ list of the same call, array for array.
template <class T>
void same_array(const T* c, std::size_t count, const tricell::PairArray<T>& cxx, const char* what) {
    if ((c == nullptr) != cxx.empty() && count > 0) {
        broken(std::string("the C API and the C++ API differ in storing ") + what);
    }
    if (c != nullptr && count > 0 &&
        (cxx.size() != count || !std::equal(cxx.begin(), cxx.end(), c, [](T a, T b) {
             return std::memcmp(&a, &b, sizeof a) == 0;
         }))) {
        broken(std::string("the C API and the C++ API differ in ") + what);
    }
}

void neighbors(FuzzedDataProvider& in, State& state) {
    tricell_box box_storage;
    const tricell_box* box = call_box(in, state, box_storage);
    std::size_t n = in.ConsumeIntegralInRange<std::size_t>(0, max_atoms);
    const std::vector<Eigen::Vector3d> x = positions(in, box != nullptr ? *box : state.box, n);
    std::vector<double> xyz(3 * n); // exactly the 3 n doubles the call may read
    for (std::size_t i = 0; i < n; ++i) {
        std::copy(x[i].data(), x[i].data() + 3, xyz.begin() + std::ptrdiff_t(3 * i));
    }
    Tables tables;
    const tricell_neighbor_options options = neighbor_options(in, n, tables);
    const double* data = n == 0 && in.ConsumeBool() ? nullptr : xyz.data();
    bool lying = false; // n disagrees with the arrays: only NULL positions, never read
    if (in.ConsumeIntegralInRange(0, 15) == 0) {
        data = nullptr;
        n = pick<std::size_t>(in, {1, 5, std::size_t(1) << 31, std::size_t(-1)});
        lying = true;
        if (n < (std::size_t(1) << 31) &&
            (options.radii != nullptr || options.species != nullptr)) {
            n = std::size_t(1) << 31; // radii and species are read for n < 2^31 - 1
        }
    }
    tricell_neighbor_search* search =
        in.ConsumeIntegralInRange(0, 15) == 0 ? nullptr : state.search;
    const bool null_options = in.ConsumeIntegralInRange(0, 15) == 0;
    const bool null_list = in.ConsumeIntegralInRange(0, 31) == 0;
    // The C++ box of the call (none for NULL or a box the C++ API refuses: a fast refusal).
    const std::optional<tricell::Box> cbox = box != nullptr ? cxx_box(*box) : std::nullopt;
    if (!lying && cbox &&
        tricell::fuzz::too_many_images(*cbox, largest_cutoff(options, n), x.size())) {
        return; // speed (differential.hpp)
    }
    if (verbose && box != nullptr && !lying) {
        std::fprintf(stderr, "tricell_neighbors\n");
        print_call(*box, x, options);
    }
    const tricell_status status = tricell_neighbors(
        search, box, data, n, null_options ? nullptr : &options, null_list ? nullptr : state.list);
    const bool ok = check_status(status, "tricell_neighbors");
    const std::string message = tricell_last_error();
    if (null_list) {
        if (ok) {
            broken("tricell_neighbors accepted a NULL list");
        }
        return;
    }
    const tricell_pairs pairs = list_pairs(state.list);
    if (!ok) {
        expect_empty(pairs, "tricell_neighbors");
    }
    if (search == nullptr || box == nullptr || null_options || lying) {
        if (ok) {
            broken("tricell_neighbors accepted a NULL argument or a NULL positions array");
        }
        return;
    }
    // The C++ API with the same arguments: the same outcome, message and arrays.
    const std::optional<tricell::NeighborOptions> copts = cxx_options(options, n);
    if (!cbox || !copts) {
        if (ok) {
            broken("tricell_neighbors accepted a box or flags the C++ API refuses");
        }
        return;
    }
    // A successful call's arrays are compared with the C++ API's on the sampled inputs; a
    // refusal (cheap) always is.
    if (!ok || compared_input) {
        tricell::NeighborList cxx;
        try {
            tricell::compute_neighbors(*cbox, x, *copts, cxx);
        } catch (const tricell::Error& e) {
            // A pair limit reads in C terms there: the field of tricell_neighbor_options.
            const auto* limit = dynamic_cast<const tricell::PairLimitError*>(&e);
            const std::string expected =
                limit != nullptr
                    ? limit->message_for("max_pairs = " + std::to_string(limit->limit()),
                                         "tricell_neighbor_options.max_pairs")
                    : std::string(e.what());
            if (ok || message != expected) {
                broken("the C API and the C++ API differ: C " + message + ", C++ " + expected);
            }
            return;
        }
        if (!ok) {
            broken("the C API refused what the C++ API accepts: " + message);
        }
        if (pairs.size != cxx.size()) {
            broken("the C API and the C++ API differ in the number of pairs");
        }
        same_array(pairs.i, pairs.size, cxx.i(), "i");
        same_array(pairs.j, pairs.size, cxx.j(), "j");
        same_array(pairs.shifts, 3 * pairs.size, cxx.shifts(), "shifts");
        same_array(pairs.distances, pairs.size, cxx.distances(), "distances");
        same_array(pairs.vectors, 3 * pairs.size, cxx.vectors(), "vectors");
    }
    if ((pairs.shifts == nullptr) == (options.shifts == 1) ||
        (pairs.distances == nullptr) == (options.distances == 1) ||
        (pairs.vectors == nullptr) == (options.vectors == 1) ||
        (pairs.offsets == nullptr) == (options.sorted == 1 || options.grouped == 1)) {
        broken("a stored quantity is NULL or one not asked for is not");
    }
    tricell::fuzz::ListView v{pairs.size,   pairs.i,       pairs.j,
                              pairs.shifts, pairs.offsets, pairs.atoms + 1};
    tricell::fuzz::check_rules(*cbox, n, options.half == 1,
                               options.sorted == 1    ? tricell::fuzz::Order::sorted
                               : options.grouped == 1 ? tricell::fuzz::Order::grouped
                                                      : tricell::fuzz::Order::any,
                               options.max_pairs, v);

    // The oracle, for one cutoff, radii or a species table.
    const tricell::NeighborOptions& c = *copts;
    const double largest = largest_cutoff(options, n);
    const auto cutoff_of = [&](std::uint32_t i, std::uint32_t j) {
        if (!c.radii.empty()) {
            return c.radii[i] + c.radii[j];
        }
        if (!c.species_cutoffs.empty()) {
            for (const auto& e : c.species_cutoffs) {
                if ((e.a == c.species[i] && e.b == c.species[j]) ||
                    (e.b == c.species[i] && e.a == c.species[j])) {
                    return e.cutoff;
                }
            }
            return 0.0;
        }
        return c.cutoff;
    };
    if (pairs.shifts == nullptr ||
        !tricell::fuzz::oracle_affordable(*cbox, x, largest, max_oracle_work)) {
        return;
    }
    compare_with_oracle(*cbox, x, largest, cutoff_of, c.half, pairs, "tricell_neighbors");
}

// Create (or replace) the Verlet handle from fuzzed options.
void verlet_create(FuzzedDataProvider& in, State& state) {
    tricell_verlet_options o;
    if (!check_status(tricell_verlet_options_init(&o), "tricell_verlet_options_init")) {
        broken("tricell_verlet_options_init failed");
    }
    Tables tables;
    o.neighbors = neighbor_options(in, 1, tables);
    // The Verlet list refuses variable cutoffs; radii (one entry, n unknown) are sometimes set.
    o.neighbors.radii = nullptr;
    o.neighbors.species = nullptr;
    o.neighbors.species_cutoffs = nullptr;
    o.neighbors.species_cutoff_count = 0;
    if (in.ConsumeIntegralInRange(0, 7) == 0) {
        o.neighbors.radii = tables.radii.empty() ? nullptr : tables.radii.data();
    }
    o.skin =
        in.ConsumeIntegralInRange(0, 4) == 0 ? real(in) : in.ConsumeFloatingPointInRange(0.0, 1.0);
    tricell_verlet* made = nullptr;
    const bool null_options = in.ConsumeIntegralInRange(0, 15) == 0;
    const tricell_status status = tricell_verlet_create(null_options ? nullptr : &o, &made);
    if (!check_status(status, "tricell_verlet_create")) {
        if (made != nullptr) {
            broken("a failed tricell_verlet_create wrote its handle");
        }
        return;
    }
    if (null_options || made == nullptr) {
        broken("tricell_verlet_create accepted NULL options or made no handle");
    }
    tricell_verlet_destroy(state.verlet);
    state.verlet = made;
    state.verlet_options = o;
    state.verlet_options.neighbors.radii = nullptr; // tables dies here
}

// One update with a box and an atom count that may change from call to call.
void verlet_update(FuzzedDataProvider& in, State& state) {
    if (state.verlet == nullptr) {
        expect_refused(tricell_verlet_update(nullptr, &state.box, nullptr, 0, nullptr),
                       "tricell_verlet_update");
        return;
    }
    tricell_box box_storage;
    const tricell_box* box = call_box(in, state, box_storage);
    const std::size_t n = in.ConsumeIntegralInRange<std::size_t>(0, max_atoms);
    const std::vector<Eigen::Vector3d> x = positions(in, box != nullptr ? *box : state.box, n);
    std::vector<double> xyz(3 * n);
    for (std::size_t i = 0; i < n; ++i) {
        std::copy(x[i].data(), x[i].data() + 3, xyz.begin() + std::ptrdiff_t(3 * i));
    }
    const tricell_neighbor_options& o = state.verlet_options.neighbors;
    if (verbose && box != nullptr) {
        std::fprintf(stderr, "Verlet update, skin %.17g\n", state.verlet_options.skin);
        print_call(*box, x, o);
    }
    int rebuilt = -7;
    const bool want_rebuilt = in.ConsumeBool();
    const std::optional<tricell::Box> cbox = box != nullptr ? cxx_box(*box) : std::nullopt;
    if (cbox &&
        tricell::fuzz::too_many_images(*cbox, o.cutoff + state.verlet_options.skin, x.size())) {
        return; // speed (differential.hpp)
    }
    const tricell_status status =
        tricell_verlet_update(state.verlet, box, xyz.data(), n, want_rebuilt ? &rebuilt : nullptr);
    const bool ok = check_status(status, "tricell_verlet_update");
    tricell_pairs pairs;
    if (!check_status(tricell_verlet_pairs(state.verlet, &pairs), "tricell_verlet_pairs")) {
        broken("tricell_verlet_pairs failed on a valid handle");
    }
    if (!ok) {
        expect_empty(pairs, "tricell_verlet_update");
        if (rebuilt != -7) {
            broken("a failed tricell_verlet_update wrote *rebuilt");
        }
        return;
    }
    if (box == nullptr) {
        broken("tricell_verlet_update accepted a NULL box");
    }
    if (want_rebuilt && rebuilt != 0 && rebuilt != 1) {
        broken("tricell_verlet_update set *rebuilt to " + std::to_string(rebuilt));
    }
    if (!cbox) {
        broken("tricell_verlet_update accepted a box the C++ API refuses");
    }
    // Grouped by i with offsets (the order within an atom is unspecified).
    if (pairs.offsets != nullptr && pairs.atoms != n) {
        broken("Verlet offsets for " + std::to_string(pairs.atoms) + " atoms, not " +
               std::to_string(n));
    }
    tricell::fuzz::check_rules(*cbox, n, o.half == 1, tricell::fuzz::Order::grouped, o.max_pairs,
                               tricell::fuzz::ListView{pairs.size, pairs.i, pairs.j, pairs.shifts,
                                                       pairs.offsets, pairs.atoms + 1});
    if (pairs.shifts == nullptr ||
        !tricell::fuzz::oracle_affordable(*cbox, x, o.cutoff, max_oracle_work)) {
        return;
    }
    const auto cutoff_of = [&](std::uint32_t, std::uint32_t) { return o.cutoff; };
    compare_with_oracle(*cbox, x, o.cutoff, cutoff_of, o.half == 1, pairs, "tricell_verlet_update");
}

// The calls that take only NULLs: each must fail with a message, touching nothing.
void null_calls(FuzzedDataProvider& in) {
    switch (in.ConsumeIntegralInRange(0, 6)) {
    case 0:
        expect_refused(tricell_neighbor_list_pairs(nullptr, nullptr),
                       "tricell_neighbor_list_pairs");
        break;
    case 1:
        expect_refused(tricell_neighbor_options_init(nullptr), "tricell_neighbor_options_init");
        break;
    case 2:
        expect_refused(tricell_neighbor_search_create(nullptr), "tricell_neighbor_search_create");
        break;
    case 3:
        expect_refused(tricell_verlet_pairs(nullptr, nullptr), "tricell_verlet_pairs");
        break;
    case 4:
        expect_refused(tricell_verlet_options_init(nullptr), "tricell_verlet_options_init");
        break;
    case 5:
        expect_refused(tricell_neighbor_list_create(nullptr), "tricell_neighbor_list_create");
        break;
    default:
        tricell_neighbor_search_destroy(nullptr);
        tricell_neighbor_list_destroy(nullptr);
        tricell_verlet_destroy(nullptr);
        break;
    }
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::uint32_t hash = tricell::fuzz::input_hash(data, size);
    threaded_input = tricell::fuzz::every_check() || hash % threaded_every == 0;
    compared_input = tricell::fuzz::every_check() || (hash / threaded_every) % compared_every == 0;
    FuzzedDataProvider in(data, size);
    State state;
    if (!check_status(tricell_neighbor_search_create(&state.search), "search_create") ||
        !check_status(tricell_neighbor_list_create(&state.list), "list_create")) {
        broken("could not create the handles");
    }
    for (int step = 0; step < 6 && in.remaining_bytes() > 0; ++step) {
        switch (in.ConsumeIntegralInRange(0, 5)) {
        case 0:
            make_box(in, state);
            break;
        case 1:
        case 2:
            neighbors(in, state);
            break;
        case 3:
            verlet_create(in, state);
            break;
        case 4:
            verlet_update(in, state);
            break;
        default:
            null_calls(in);
            break;
        }
    }
    return 0;
}
