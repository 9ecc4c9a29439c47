// tricell_verlet_*: a VerletList behind a handle; update() reports whether it rebuilt.
#include "tricell/verlet.hpp"

#include "tricell/error.hpp"

#include "boundary.hpp"
#include "translate.hpp"

using namespace tricell;
using namespace tricell::c_api;

struct tricell_verlet {
    VerletList verlet;
    Quantities stored;
};

namespace {

VerletOptions to_verlet_options(const tricell_verlet_options& options) {
    const NeighborOptions neighbors = to_options(options.neighbors);
    if (neighbors.sorted) {
        detail::fail<InvalidArgument>("options.neighbors.sorted must be 0 for a Verlet list "
                                      "(its pairs are always grouped by i)");
    }
    VerletOptions out;
    out.cutoff = neighbors.cutoff;
    out.skin = options.skin;
    out.half = neighbors.half;
    out.quantities = neighbors.quantities;
    out.threads = neighbors.threads;
    out.max_pairs = neighbors.max_pairs;
    out.validate();
    return out;
}

} // namespace

extern "C" tricell_status tricell_verlet_options_init(tricell_verlet_options* options) {
    return guarded([&] {
        require_pointer(options, "tricell_verlet_options_init", "options");
        const VerletOptions defaults;
        NeighborOptions neighbors;
        neighbors.cutoff = defaults.cutoff;
        neighbors.half = defaults.half;
        neighbors.quantities = defaults.quantities;
        neighbors.threads = defaults.threads;
        neighbors.max_pairs = defaults.max_pairs;
        options->neighbors = to_c_options(neighbors);
        options->skin = defaults.skin;
    });
}

extern "C" tricell_status tricell_verlet_create(const tricell_verlet_options* options,
                                                tricell_verlet** verlet) {
    return guarded([&] {
        require_pointer(options, "tricell_verlet_create", "options");
        require_pointer(verlet, "tricell_verlet_create", "verlet");
        const VerletOptions cxx_options = to_verlet_options(*options);
        *verlet = new tricell_verlet{VerletList(cxx_options), cxx_options.quantities};
    });
}

extern "C" void tricell_verlet_destroy(tricell_verlet* verlet) {
    delete verlet;
}

extern "C" tricell_status tricell_verlet_update(tricell_verlet* verlet, const tricell_box* box,
                                                const double* positions, std::size_t n,
                                                int* rebuilt) {
    return guarded([&] {
        require_pointer(verlet, "tricell_verlet_update", "verlet");
        try {
            require_pointer(box, "tricell_verlet_update", "box");
            const bool did_rebuild = verlet->verlet.update(to_box(*box), PointsView(positions, n));
            if (rebuilt != nullptr) {
                *rebuilt = did_rebuild ? 1 : 0;
            }
        } catch (...) {
            verlet->verlet.reset(); // empty pairs, and the next update rebuilds
            throw;
        }
    });
}

extern "C" tricell_status tricell_verlet_pairs(const tricell_verlet* verlet, tricell_pairs* pairs) {
    return guarded([&] {
        require_pointer(verlet, "tricell_verlet_pairs", "verlet");
        require_pointer(pairs, "tricell_verlet_pairs", "pairs");
        *pairs = to_pairs(verlet->verlet.pairs(), verlet->stored, true);
    });
}
