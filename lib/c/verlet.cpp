// tricell_verlet_*: a VerletList behind a handle; update() reports whether it rebuilt.
#include "tricell/verlet.hpp"

#include <cstdint>

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
    VerletOptions out; // its neighbours' defaults (cells per list radius) where C has no field
    // The atom count is not known here. Variable cutoffs are refused by
    // VerletOptions::validate(), which only needs to see that they are set: a one-atom stand-in
    // tells it so without reading the caller's arrays.
    tricell_neighbor_options neighbors = options.neighbors;
    const double stand_in_radius = 0;
    const std::int32_t stand_in_species = 0;
    neighbors.radii = neighbors.radii != nullptr ? &stand_in_radius : nullptr;
    neighbors.species = neighbors.species != nullptr ? &stand_in_species : nullptr;
    to_options(neighbors, 1, out.neighbors);
    out.skin = options.skin;
    out.validate();
    return out;
}

} // namespace

extern "C" tricell_status tricell_verlet_options_init(tricell_verlet_options* options) {
    return guarded([&] {
        require_pointer(options, "tricell_verlet_options_init", "options");
        const VerletOptions defaults;
        options->neighbors = to_c_options(defaults.neighbors);
        options->skin = defaults.skin;
    });
}

extern "C" tricell_status tricell_verlet_create(const tricell_verlet_options* options,
                                                tricell_verlet** verlet) {
    return guarded([&] {
        require_pointer(options, "tricell_verlet_create", "options");
        require_pointer(verlet, "tricell_verlet_create", "verlet");
        const VerletOptions cxx_options = to_verlet_options(*options);
        *verlet = new tricell_verlet{VerletList(cxx_options), cxx_options.neighbors.quantities};
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
