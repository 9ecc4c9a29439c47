// tricell_verify: the C face of tricell::verify. The C list's 32-bit columns are widened into
// the int64 arrays of tricell::PairArrays; the report's counts are copied and its texts
// truncated into the C struct's buffers.
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "boundary.hpp"
#include "translate.hpp"
#include "tricell/verify.hpp"

using namespace tricell;
using namespace tricell::c_api;

namespace {

template <std::size_t N> void copy_text(const std::string& text, char (&buffer)[N]) {
    const std::size_t length = std::min(text.size(), N - 1);
    std::memcpy(buffer, text.data(), length);
    buffer[length] = '\0';
}

} // namespace

extern "C" tricell_status tricell_verify(const tricell_box* box, const double* positions,
                                         std::size_t n, const tricell_neighbor_options* options,
                                         const tricell_pairs* pairs,
                                         tricell_verify_report* report) {
    return guarded([&] {
        require_pointer(box, "tricell_verify", "box");
        require_pointer(options, "tricell_verify", "options");
        require_pointer(pairs, "tricell_verify", "pairs");
        require_pointer(report, "tricell_verify", "report");
        if (pairs->size > 0) {
            require_pointer(pairs->i, "tricell_verify", "pairs->i");
            require_pointer(pairs->j, "tricell_verify", "pairs->j");
        }
        NeighborOptions cxx_options;
        to_options(*options, n, cxx_options);
        const std::size_t size = pairs->size;
        std::vector<std::int64_t> i(pairs->i, pairs->i + size);
        std::vector<std::int64_t> j(pairs->j, pairs->j + size);
        std::vector<std::int64_t> shifts;
        if (pairs->shifts != nullptr) {
            shifts.assign(pairs->shifts, pairs->shifts + 3 * size);
        }
        const PairArrays arrays{size,
                                i.data(),
                                j.data(),
                                pairs->shifts != nullptr ? shifts.data() : nullptr,
                                pairs->distances,
                                pairs->vectors};
        const VerifyReport result =
            verify(to_box(*box), PointsView(positions, n), cxx_options, arrays);
        tricell_verify_report out{};
        out.ok = result.ok ? 1 : 0;
        out.entries = result.entries;
        out.expected = result.expected;
        out.matched = result.matched;
        out.near_cutoff = result.near_cutoff;
        out.missing = result.missing;
        out.extra = result.extra;
        out.duplicates = result.duplicates;
        out.rule_breaks = result.rule_breaks;
        out.wrong_values = result.wrong_values;
        copy_text(result.reference, out.reference);
        copy_text(result.message, out.message);
        *report = out;
    });
}
