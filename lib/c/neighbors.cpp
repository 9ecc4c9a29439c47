// tricell_neighbors and its handles: NeighborSearch::build + compute into a reused
// NeighborList, and a view of the list's arrays without a copy.
#include "boundary.hpp"
#include "translate.hpp"

using namespace tricell;
using namespace tricell::c_api;

extern "C" tricell_status tricell_neighbor_options_init(tricell_neighbor_options* options) {
    return guarded([&] {
        require_pointer(options, "tricell_neighbor_options_init", "options");
        *options = to_c_options(NeighborOptions());
    });
}

extern "C" tricell_status tricell_neighbor_search_create(tricell_neighbor_search** search) {
    return guarded([&] {
        require_pointer(search, "tricell_neighbor_search_create", "search");
        *search = new tricell_neighbor_search();
    });
}

extern "C" void tricell_neighbor_search_destroy(tricell_neighbor_search* search) {
    delete search;
}

extern "C" tricell_status tricell_neighbor_list_create(tricell_neighbor_list** list) {
    return guarded([&] {
        require_pointer(list, "tricell_neighbor_list_create", "list");
        *list = new tricell_neighbor_list();
    });
}

extern "C" void tricell_neighbor_list_destroy(tricell_neighbor_list* list) {
    delete list;
}

extern "C" tricell_status tricell_neighbors(tricell_neighbor_search* search, const tricell_box* box,
                                            const double* positions, std::size_t n,
                                            const tricell_neighbor_options* options,
                                            tricell_neighbor_list* list) {
    return guarded([&] {
        require_pointer(list, "tricell_neighbors", "list");
        // Empty from here on until the new pairs are complete.
        list->list.clear();
        list->stored = Quantities{false, false, false};
        list->with_offsets = false;
        require_pointer(search, "tricell_neighbors", "search");
        require_pointer(box, "tricell_neighbors", "box");
        require_pointer(options, "tricell_neighbors", "options");
        NeighborOptions& cxx_options = search->options;
        to_options(*options, n, cxx_options);
        search->search.build(to_box(*box), PointsView(positions, n), cxx_options);
        search->search.compute(list->list);
        list->stored = cxx_options.quantities;
        list->with_offsets = cxx_options.with_offsets();
    });
}

extern "C" tricell_status tricell_neighbor_list_pairs(const tricell_neighbor_list* list,
                                                      tricell_pairs* pairs) {
    return guarded([&] {
        require_pointer(list, "tricell_neighbor_list_pairs", "list");
        require_pointer(pairs, "tricell_neighbor_list_pairs", "pairs");
        *pairs = to_pairs(list->list, list->stored, list->with_offsets);
    });
}
