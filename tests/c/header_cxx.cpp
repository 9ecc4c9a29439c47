// tricell.h compiled as C++ (with -Werror): the header works from C++ too, names and types
// included, and its declarations have C linkage.
#include "tricell.h"

#include <type_traits>

static_assert(std::is_same<decltype(&tricell_neighbors),
                           tricell_status (*)(
                               tricell_neighbor_search*, const tricell_box*, const double*, size_t,
                               const tricell_neighbor_options*, tricell_neighbor_list*)>::value,
              "tricell_neighbors as documented");
static_assert(std::is_standard_layout<tricell_pairs>::value, "a C struct");
static_assert(TRICELL_OK == 0, "success is 0");

int main() {
    tricell_neighbor_options options;
    return tricell_neighbor_options_init(&options) == TRICELL_OK && options.cutoff == 0 ? 0 : 1;
}
