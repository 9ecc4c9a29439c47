// docs/cpp.md, "The box": the page's example as written, then what its comments promise: the
// wrapped point lies in [0, 1) along the periodic axes with s = wrapped + image, and the
// minimum image is d + H shift, no longer than any other translate along the periodic axes.
#include "the_box_includes.inc"

#include "doc_check.hpp"

int main() {
#include "the_box_block.inc"

    for (int axis = 0; axis < 2; ++axis) {
        DOC_CHECK(w.wrapped[axis] >= 0 && w.wrapped[axis] < 1, "w.wrapped in [0, 1)");
    }
    DOC_CHECK((w.wrapped + w.image.cast<double>() - s).norm() < 1e-12, "s = wrapped + image");
    const Eigen::Vector3d d(9.7, 10.2, -0.3);
    DOC_CHECK((mi.vector - (d + box.matrix() * mi.shift.cast<double>())).norm() < 1e-12,
              "mi.vector == d + H * mi.shift");
    DOC_CHECK(mi.shift[2] == 0, "no shift along the open axis c");
    for (int a = -3; a <= 3; ++a) {
        for (int b = -3; b <= 3; ++b) {
            const Eigen::Vector3d t = d + box.matrix() * Eigen::Vector3d(a, b, 0);
            DOC_CHECK(mi.vector.norm() <= t.norm() + 1e-12, "the shortest periodic translate");
        }
    }
    return 0;
}
