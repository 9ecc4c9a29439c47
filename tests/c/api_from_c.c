/* The C API used from C, compiled as C99 with -Wall -Wextra -pedantic -Werror: every function
 * of tricell.h, on an FCC crystal whose neighbour counts are known exactly (12 at the nearest
 * distance a / sqrt 2, 6 more at a), in a triclinic primitive cell and in a cubic one. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "tricell.h"

static int failures = 0;

#define CHECK(condition)                                                                           \
    do {                                                                                           \
        if (!(condition)) {                                                                        \
            fprintf(stderr, "%s:%d: CHECK(%s) failed; last error: %s\n", __FILE__, __LINE__,       \
                    #condition, tricell_last_error());                                             \
            ++failures;                                                                            \
        }                                                                                          \
    } while (0)

/* Each atom of a perfect crystal has the same number of neighbours. */
static void check_counts(const tricell_pairs* pairs, size_t atoms, size_t per_atom) {
    size_t a;
    CHECK(pairs->size == atoms * per_atom);
    CHECK(pairs->offsets != NULL && pairs->atoms == atoms);
    if (pairs->offsets == NULL) {
        return;
    }
    for (a = 0; a < atoms; ++a) {
        CHECK(pairs->offsets[a + 1] - pairs->offsets[a] == per_atom);
    }
}

int main(void) {
    const double a = 3.6;
    const int periodic[3] = {1, 1, 1};
    tricell_box primitive, cubic;
    tricell_neighbor_search* search = NULL;
    tricell_neighbor_list* list = NULL;
    tricell_neighbor_options options;
    tricell_pairs pairs;
    tricell_verify_report report;
    tricell_verlet_options verlet_options;
    tricell_verlet* verlet = NULL;
    double origin[3] = {0.25, -7.5, 100.0}; /* any position, even far outside */
    double fcc[12];
    const double cube_rows[9] = {3.6, 0, 0, 0, 3.6, 0, 0, 0, 3.6};
    const double basis[4][3] = {{0, 0, 0}, {0.5, 0.5, 0}, {0.5, 0, 0.5}, {0, 0.5, 0.5}};
    size_t k;
    int rebuilt = -1;

    CHECK(strcmp(tricell_version(), TRICELL_VERSION_STRING) == 0);
    CHECK(tricell_version_major() == TRICELL_VERSION_MAJOR);
    CHECK(tricell_version_minor() == TRICELL_VERSION_MINOR);
    CHECK(tricell_version_patch() == TRICELL_VERSION_PATCH);

    /* The primitive FCC cell: a = b = c = a0 / sqrt 2, all angles 60 degrees. */
    CHECK(tricell_box_from_parameters(a / sqrt(2.0), a / sqrt(2.0), a / sqrt(2.0), 60, 60, 60,
                                      periodic, &primitive) == TRICELL_OK);
    CHECK(tricell_box_from_rows(cube_rows, periodic, &cubic) == TRICELL_OK);
    CHECK(tricell_box_from_columns(cube_rows, periodic, &cubic) == TRICELL_OK);
    for (k = 0; k < 4; ++k) {
        fcc[3 * k] = a * basis[k][0];
        fcc[3 * k + 1] = a * basis[k][1];
        fcc[3 * k + 2] = a * basis[k][2];
    }

    CHECK(tricell_neighbor_search_create(&search) == TRICELL_OK);
    CHECK(tricell_neighbor_list_create(&list) == TRICELL_OK);
    CHECK(tricell_neighbor_options_init(&options) == TRICELL_OK);
    options.sorted = 1;
    options.vectors = 1;

    options.cutoff = 0.9 * a; /* 12 nearest neighbours */
    CHECK(tricell_neighbors(search, &primitive, origin, 1, &options, list) == TRICELL_OK);
    CHECK(tricell_neighbor_list_pairs(list, &pairs) == TRICELL_OK);
    check_counts(&pairs, 1, 12);
    for (k = 0; k < pairs.size; ++k) {
        CHECK(fabs(pairs.distances[k] - a / sqrt(2.0)) < 1e-12);
        CHECK(pairs.i[k] == 0 && pairs.j[k] == 0);
    }
    options.cutoff = 1.1 * a; /* 12 + 6 */
    CHECK(tricell_neighbors(search, &cubic, fcc, 4, &options, list) == TRICELL_OK);
    CHECK(tricell_neighbor_list_pairs(list, &pairs) == TRICELL_OK);
    check_counts(&pairs, 4, 18);
    options.half = 1;
    options.sorted = 0;
    CHECK(tricell_neighbors(search, &cubic, fcc, 4, &options, list) == TRICELL_OK);
    CHECK(tricell_neighbor_list_pairs(list, &pairs) == TRICELL_OK);
    CHECK(pairs.size == 4 * 18 / 2 && pairs.offsets == NULL);
    /* The half list verified, then the same list with its last pair left out. */
    CHECK(tricell_verify(&cubic, fcc, 4, &options, &pairs, &report) == TRICELL_OK);
    CHECK(report.ok == 1 && report.entries == 36 && report.expected == 36);
    CHECK(strcmp(report.reference, "brute force") == 0);
    pairs.size -= 1;
    CHECK(tricell_verify(&cubic, fcc, 4, &options, &pairs, &report) == TRICELL_OK);
    CHECK(report.ok == 0 && report.missing == 1 && strstr(report.message, "is missing") != NULL);

    /* An error: the status, the C++ message, and an empty list. */
    options.cutoff = -1.5;
    CHECK(tricell_neighbors(search, &cubic, fcc, 4, &options, list) ==
          TRICELL_ERROR_INVALID_ARGUMENT);
    CHECK(strcmp(tricell_last_error(), "cutoff must be > 0 (got -1.5)") == 0);
    CHECK(tricell_neighbor_list_pairs(list, &pairs) == TRICELL_OK && pairs.size == 0);
    CHECK(strcmp(tricell_last_error(), "") == 0);

    CHECK(tricell_verlet_options_init(&verlet_options) == TRICELL_OK);
    verlet_options.neighbors.cutoff = 0.9 * a;
    verlet_options.skin = 0.3;
    CHECK(tricell_verlet_create(&verlet_options, &verlet) == TRICELL_OK);
    CHECK(tricell_verlet_update(verlet, &cubic, fcc, 4, &rebuilt) == TRICELL_OK && rebuilt == 1);
    fcc[0] += 0.01; /* a small move: no rebuild */
    CHECK(tricell_verlet_update(verlet, &cubic, fcc, 4, &rebuilt) == TRICELL_OK && rebuilt == 0);
    CHECK(tricell_verlet_pairs(verlet, &pairs) == TRICELL_OK);
    CHECK(pairs.size == 4 * 12 && pairs.offsets != NULL && pairs.atoms == 4);

    tricell_verlet_destroy(verlet);
    tricell_neighbor_list_destroy(list);
    tricell_neighbor_search_destroy(search);
    if (failures == 0) {
        printf("tricell C API from C: ok\n");
    }
    return failures == 0 ? 0 : 1;
}
