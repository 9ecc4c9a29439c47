// Placeholder until the adaptive octree lands (issue 9): refuses with a clear message.
#include "backends/backend.hpp"
#include "tricell/error.hpp"

namespace tricell::detail {

std::unique_ptr<Backend> make_octree_backend() {
    fail<InvalidArgument>("the octree backend is not built yet");
}

} // namespace tricell::detail
