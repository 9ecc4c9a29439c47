// The backend registry: one table of every search backend, with its name and its factory. The
// names, parse_backend(), the validation of NeighborOptions::backend, the messages that list the
// choices, the pool of backend objects a search keeps, and every list the command line, the C
// API, Python, the tests and benchmarks/compare show come from this table. Adding a backend
// touches its own file in lib/backends/ and one line of the table (registry.cpp).
#pragma once

#include <cstddef>
#include <memory>

#include "backends/backend.hpp"
#include "tricell/neighbor_list.hpp"

namespace tricell::detail {

/// One row of the table. `make` is null for `automatic`, which is a choice, not a structure.
struct BackendEntry {
    SearchBackend backend;
    const char* name;
    std::unique_ptr<Backend> (*make)();
};

/// The table, `automatic` first.
const BackendEntry* backend_table(std::size_t& count);

/// The row of `backend`, or null for a value outside the enumeration.
const BackendEntry* find_backend(SearchBackend backend);

/// A new object of a concrete backend (not `automatic`).
std::unique_ptr<Backend> make_backend(SearchBackend backend);

/// One object of each backend, kept between builds so that their buffers are reused.
class BackendPool {
  public:
    Backend& get(SearchBackend backend);

  private:
    static constexpr std::size_t slots = 8;
    std::unique_ptr<Backend> pool_[slots];
};

} // namespace tricell::detail
