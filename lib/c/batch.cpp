// tricell_neighbors_batch (and _indexed, its atoms numbered per structure or across the batch)
// and its list handle: the C structures become BatchStructures (each box checked and named by
// its structure), compute_neighbors_batch fills a reused BatchList, and a view hands out its
// shared arrays without a copy.
#include "boundary.hpp"
#include "translate.hpp"

#include "tricell/error.hpp"

using namespace tricell;
using namespace tricell::c_api;

extern "C" tricell_status tricell_batch_list_create(tricell_batch_list** list) {
    return guarded([&] {
        require_pointer(list, "tricell_batch_list_create", "list");
        *list = new tricell_batch_list();
    });
}

extern "C" void tricell_batch_list_destroy(tricell_batch_list* list) {
    delete list;
}

namespace {

// The batch call behind both C functions; `name` is the function the caller called.
tricell_status neighbors_batch(const char* name, const tricell_structure* structures,
                               std::size_t count, const tricell_neighbor_options* options,
                               int indices, tricell_batch_list* list) {
    return guarded([&] {
        require_pointer(list, name, "list");
        // Empty from here on until the new pairs are complete.
        list->list.clear();
        list->stored = Quantities{false, false, false};
        list->with_offsets = false;
        require_pointer(options, name, "options");
        if (indices != TRICELL_BATCH_LOCAL && indices != TRICELL_BATCH_GLOBAL) {
            detail::fail<InvalidArgument>(name,
                                          ": indices must be TRICELL_BATCH_LOCAL (0) or "
                                          "TRICELL_BATCH_GLOBAL (1) (got ",
                                          indices, ")");
        }
        if (count > 0) {
            require_pointer(structures, name, "structures");
        }
        if (options->radii != nullptr || options->species != nullptr) {
            detail::fail<InvalidArgument>(
                name, ": options.radii and options.species must be NULL (one set of options "
                      "serves every structure of a batch)");
        }
        to_options(*options, 0, list->options);
        list->structures.clear();
        list->structures.reserve(count);
        for (std::size_t s = 0; s < count; ++s) {
            try {
                list->structures.push_back(
                    BatchStructure{to_box(structures[s].box),
                                   PointsView(structures[s].positions, structures[s].n)});
            } catch (const Error&) {
                detail::rethrow_for_structure(s);
            }
        }
        compute_neighbors_batch(list->structures, list->options, list->list,
                                indices == TRICELL_BATCH_GLOBAL ? BatchIndices::global
                                                                : BatchIndices::local);
        list->stored = list->options.quantities;
        list->with_offsets = list->options.with_offsets();
    });
}

} // namespace

extern "C" tricell_status tricell_neighbors_batch(const tricell_structure* structures,
                                                  std::size_t count,
                                                  const tricell_neighbor_options* options,
                                                  tricell_batch_list* list) {
    return neighbors_batch("tricell_neighbors_batch", structures, count, options,
                           TRICELL_BATCH_LOCAL, list);
}

extern "C" tricell_status tricell_neighbors_batch_indexed(const tricell_structure* structures,
                                                          std::size_t count,
                                                          const tricell_neighbor_options* options,
                                                          int indices, tricell_batch_list* list) {
    return neighbors_batch("tricell_neighbors_batch_indexed", structures, count, options, indices,
                           list);
}

extern "C" tricell_status tricell_batch_list_pairs(const tricell_batch_list* list,
                                                   tricell_batch_pairs* pairs) {
    return guarded([&] {
        require_pointer(list, "tricell_batch_list_pairs", "list");
        require_pointer(pairs, "tricell_batch_list_pairs", "pairs");
        *pairs = to_batch_pairs(list->list, list->stored, list->with_offsets);
    });
}
