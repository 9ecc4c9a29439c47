// tricell_box_from_*: the C++ named constructors, their validation and their messages.
#include "boundary.hpp"
#include "translate.hpp"

using namespace tricell;
using namespace tricell::c_api;

namespace {

Eigen::Matrix3d row_major(const double m[9]) {
    Eigen::Matrix3d out;
    for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) {
            out(r, c) = m[3 * r + c];
        }
    }
    return out;
}

} // namespace

extern "C" tricell_status tricell_box_from_rows(const double rows[9], const int periodic[3],
                                                tricell_box* box) {
    return guarded([&] {
        require_pointer(rows, "tricell_box_from_rows", "rows");
        require_pointer(periodic, "tricell_box_from_rows", "periodic");
        require_pointer(box, "tricell_box_from_rows", "box");
        *box = to_c_box(Box::from_rows(row_major(rows), to_periodicity(periodic)));
    });
}

extern "C" tricell_status tricell_box_from_columns(const double columns[9], const int periodic[3],
                                                   tricell_box* box) {
    return guarded([&] {
        require_pointer(columns, "tricell_box_from_columns", "columns");
        require_pointer(periodic, "tricell_box_from_columns", "periodic");
        require_pointer(box, "tricell_box_from_columns", "box");
        *box = to_c_box(Box::from_columns(row_major(columns), to_periodicity(periodic)));
    });
}

extern "C" tricell_status tricell_box_from_parameters(double a, double b, double c, double alpha,
                                                      double beta, double gamma,
                                                      const int periodic[3], tricell_box* box) {
    return guarded([&] {
        require_pointer(periodic, "tricell_box_from_parameters", "periodic");
        require_pointer(box, "tricell_box_from_parameters", "box");
        *box =
            to_c_box(Box::from_parameters(a, b, c, alpha, beta, gamma, to_periodicity(periodic)));
    });
}
