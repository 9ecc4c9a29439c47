// The communication model of tricell/mpi/traffic.hpp.
#include "tricell/mpi/traffic.hpp"

#include <algorithm>
#include <cmath>

#include "tricell/error.hpp"

namespace tricell::mpi {

HaloModel halo_model(const Decomposition& decomposition, const Box& box, double reach,
                     GhostSet ghosts) {
    if (!(std::isfinite(reach) && reach > 0)) {
        detail::fail<InvalidArgument>("halo_model: reach must be > 0 (got ", reach, ")");
    }
    double all = 1, self = 1;
    int neighborhood = 1;
    for (int k = 0; k < 3; ++k) {
        if (!box.periodicity()[k]) {
            detail::fail<InvalidArgument>("halo_model: axis ", k,
                                          " is open; the model is for periodic boxes");
        }
        const int d = decomposition.dims()[std::size_t(k)];
        const double h = reach * d / box.perpendicular_widths()[k]; // in domain widths
        all *= 1 + 2 * h;
        if (d == 1) {
            self *= 1 + 2 * h;
        }
        neighborhood *= std::min(d, 2 * int(std::ceil(h)) + 1);
    }
    HaloModel out;
    const double share = ghosts == GhostSet::upper ? 0.5 : 1.0;
    out.ghosts_per_atom = share * (all - 1);
    out.sent_ghosts_per_atom = share * (all - self);
    out.messages = neighborhood - 1;
    return out;
}

} // namespace tricell::mpi
