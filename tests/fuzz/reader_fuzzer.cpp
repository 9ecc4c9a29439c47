// libFuzzer harness for one structure reader (CIF, POSCAR or extended XYZ, chosen at compile
// time by TRICELL_FUZZ_FORMAT): the input bytes are the contents of a file, parsed from memory
// with tricell::io::parse_structure.
//
// What counts as a failure: a crash, a sanitizer report, a hang or a large allocation (the
// -timeout and -rss_limit_mb of libFuzzer), an exception that is not a tricell::Error, an
// error message that is not one line, or a Structure that breaks its own invariants (per-atom
// arrays of different lengths, a non-finite position or occupancy, an empty species).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include <tricell/error.hpp>
#include <tricell/io/structure.hpp>

namespace {

[[noreturn]] void broken(const char* what, const std::string& detail) {
    std::fprintf(stderr, "reader_fuzzer: %s: %s\n", what, detail.c_str());
    std::abort();
}

void check(const tricell::io::Structure& s) {
    const std::size_t n = s.positions.size();
    if (s.species.size() != n || s.occupancies.size() != n || s.labels.size() != n) {
        broken("per-atom arrays differ in length", std::to_string(n));
    }
    if (!s.box.matrix().allFinite() || !(s.box.volume() > 0)) {
        broken("box is not finite or has no volume", std::to_string(s.box.volume()));
    }
    for (std::size_t i = 0; i < n; ++i) {
        if (!s.positions[i].allFinite()) {
            broken("position is not finite", std::to_string(i));
        }
        if (!std::isfinite(s.occupancies[i])) {
            broken("occupancy is not finite", std::to_string(i));
        }
        if (s.species[i].empty()) {
            broken("empty species", std::to_string(i));
        }
    }
    (void)tricell::io::formula(s);
    (void)tricell::io::occupied_count(s);
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    tricell::io::ReadOptions options;
    options.format = tricell::io::Format::TRICELL_FUZZ_FORMAT;
    try {
        check(tricell::io::parse_structure(text, "fuzz", options));
    } catch (const tricell::Error& e) {
        const std::string message = e.what();
        if (message.find('\n') != std::string::npos || message.find('\r') != std::string::npos) {
            broken("error message is not one line", message);
        }
    }
    return 0;
}
