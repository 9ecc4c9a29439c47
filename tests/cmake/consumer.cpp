// A minimal consumer of tricell::core: builds a box and checks a minimum image.
#include <cmath>
#include <cstdio>

#include <tricell/tricell.hpp>

int main() {
    const tricell::Box box = tricell::Box::from_parameters(3.0, 3.0, 3.0, 90, 90, 90);
    const double d =
        box.minimum_image_distance(tricell::Cartesian(0.1, 0, 0), tricell::Cartesian(2.9, 0, 0));
    if (std::abs(d - 0.2) > 1e-12) {
        std::printf("unexpected minimum-image distance %g\n", d);
        return 1;
    }
    std::printf("tricell consumer ok\n");
    return 0;
}
