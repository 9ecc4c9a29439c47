/* A minimal C consumer of tricell::c: the 12 nearest neighbours of an FCC primitive cell. */
#include <stdio.h>

#include <tricell.h>

int main(void) {
    const int periodic[3] = {1, 1, 1};
    const double x[3] = {0, 0, 0};
    tricell_box box;
    tricell_neighbor_search* search = NULL;
    tricell_neighbor_list* list = NULL;
    tricell_neighbor_options options;
    tricell_pairs pairs;
    int ok;

    tricell_neighbor_options_init(&options);
    options.cutoff = 3.0;
    ok = tricell_box_from_parameters(2.5, 2.5, 2.5, 60, 60, 60, periodic, &box) == TRICELL_OK &&
         tricell_neighbor_search_create(&search) == TRICELL_OK &&
         tricell_neighbor_list_create(&list) == TRICELL_OK &&
         tricell_neighbors(search, &box, x, 1, &options, list) == TRICELL_OK &&
         tricell_neighbor_list_pairs(list, &pairs) == TRICELL_OK && pairs.size == 12;
    tricell_neighbor_list_destroy(list);
    tricell_neighbor_search_destroy(search);
    if (!ok) {
        printf("tricell C consumer failed: %s\n", tricell_last_error());
        return 1;
    }
    printf("tricell C consumer ok (tricell %s)\n", tricell_version());
    return 0;
}
