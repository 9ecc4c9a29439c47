/* tricell.h: the C API of tricell (C99; also valid C++). Link tricell::c (libtricell_c).
 *
 * Conventions (every function follows them; docs/contract.md):
 *   - Positions: N x 3 doubles, row-major (x0 y0 z0 x1 y1 z1 ...), Cartesian, in the caller's
 *     length unit. They may lie anywhere, even many box lengths outside the box.
 *   - Box: three lattice vectors a, b, c. tricell_box_from_rows() takes them as the rows of a
 *     row-major 3 x 3 array (as POSCAR, ASE and pymatgen list them), tricell_box_from_columns()
 *     as its columns (H with r = H s). Periodicity: one int per axis, 0 (open) or 1 (periodic).
 *   - A pair (i, j, S): 0-based atom indices, S an integer image shift (Sa, Sb, Sc) relative to
 *     the positions AS GIVEN, so D = x_j - x_i + Sa a + Sb b + Sc c, d = |D|. A pair counts when
 *     d < cutoff (strict). A full list holds every such (i, j, S) except (i, i, 0); a half list
 *     one of (i, j, S), (j, i, -S): i < j, or i == j with S lexicographically positive.
 *   - Status: every function that can fail returns a tricell_status; TRICELL_OK is 0. On failure
 *     tricell_last_error() gives the message (the text of the C++ error, e.g. "cutoff must be > 0
 *     (got -1.5)"), kept per thread until that thread's next call; on success it is "". No
 *     function throws, aborts, or writes anything on failure: outputs keep their old contents,
 *     except a list, which is left empty.
 *   - Handles (search, list, Verlet) are created by *_create() and freed by *_destroy(), which
 *     accepts NULL. A handle may be used by one thread at a time; distinct handles from any
 *     number of threads at once.
 */
#ifndef TRICELL_H
#define TRICELL_H

#include <stddef.h>
#include <stdint.h>

#define TRICELL_VERSION_MAJOR 0
#define TRICELL_VERSION_MINOR 1
#define TRICELL_VERSION_PATCH 0
#define TRICELL_VERSION_STRING "0.1.0"
/* MAJOR * 10000 + MINOR * 100 + PATCH, for #if comparisons. */
#define TRICELL_VERSION                                                                            \
    (TRICELL_VERSION_MAJOR * 10000 + TRICELL_VERSION_MINOR * 100 + TRICELL_VERSION_PATCH)

#if defined(_WIN32)
#if defined(TRICELL_C_BUILDING)
#define TRICELL_C_API __declspec(dllexport)
#else
#define TRICELL_C_API __declspec(dllimport)
#endif
#elif defined(__GNUC__)
#define TRICELL_C_API __attribute__((visibility("default")))
#else
#define TRICELL_C_API
#endif

#ifdef __cplusplus
extern "C" {
#endif

typedef enum tricell_status {
    TRICELL_OK = 0,
    TRICELL_ERROR_INVALID_ARGUMENT = 1, /* a NULL pointer, a bad value, a non-finite number */
    TRICELL_ERROR_GEOMETRY = 2,         /* a singular or flat box, a zero periodic vector */
    TRICELL_ERROR_OUT_OF_MEMORY = 3,
    TRICELL_ERROR_INTERNAL = 4 /* anything else (a bug: please report the message) */
} tricell_status;

/* The message of this thread's last failed call, "" after a successful one. Never NULL; valid
 * until this thread's next call into tricell. At most 1023 bytes are kept. */
TRICELL_C_API const char* tricell_last_error(void);

/* The library's version (compare with the TRICELL_VERSION_* macros of the header). */
TRICELL_C_API const char* tricell_version(void);
TRICELL_C_API int tricell_version_major(void);
TRICELL_C_API int tricell_version_minor(void);
TRICELL_C_API int tricell_version_patch(void);

/* ---- Box -------------------------------------------------------------------------------- */

/* A validated box, a plain value (no destroy). vectors[k] is lattice vector k (0 = a, 1 = b,
 * 2 = c) in Cartesian components; periodic[k] is 0 or 1. Filled by the functions below; a box
 * written by hand is checked again by every function that takes it. Open axes need no vector: a
 * zero one (a molecule's all-zero box, a slab's zero c) is completed by a unit vector orthogonal
 * to the others (docs/contract.md), which the functions below write into vectors. */
typedef struct tricell_box {
    double vectors[3][3];
    int periodic[3];
} tricell_box;

/* rows[3 * k + c]: component c of lattice vector k. */
TRICELL_C_API tricell_status tricell_box_from_rows(const double rows[9], const int periodic[3],
                                                   tricell_box* box);
/* columns[3 * c + k]: component c of lattice vector k (the matrix H, r = H s, row-major). */
TRICELL_C_API tricell_status tricell_box_from_columns(const double columns[9],
                                                      const int periodic[3], tricell_box* box);
/* Lengths a, b, c and angles alpha = (b, c), beta = (a, c), gamma = (a, b) in degrees; a along
 * x, b in the xy plane, c completing a right-handed frame (as pymatgen, ASE and LAMMPS). */
TRICELL_C_API tricell_status tricell_box_from_parameters(double a, double b, double c, double alpha,
                                                         double beta, double gamma,
                                                         const int periodic[3], tricell_box* box);

/* ---- Neighbour lists -------------------------------------------------------------------- */

/* Which search structure bins the atoms. The result never depends on it (nor on threads), only
 * the speed does. */
typedef enum tricell_backend {
    TRICELL_BACKEND_AUTOMATIC = 0, /* chosen per call from the cost model (the default) */
    TRICELL_BACKEND_DENSE = 1,     /* a dense cell grid, atoms sorted by cell */
    TRICELL_BACKEND_LINKED = 2,    /* the same grid as linked cells */
    TRICELL_BACKEND_HASH = 3,      /* compact hashing of the non-empty cells */
    TRICELL_BACKEND_OCTREE = 4,    /* an adaptive octree */
    TRICELL_BACKEND_DIRECT = 5     /* every pair through every image: tiny cells */
} tricell_backend;

/* One entry of a per-species cutoff table: pairs of species a and b (either order) count when
 * d < cutoff. */
typedef struct tricell_species_cutoff {
    int32_t a;
    int32_t b;
    double cutoff;
} tricell_species_cutoff;

/* Options of tricell_neighbors(). Start from tricell_neighbor_options_init(), then set cutoff
 * (or radii, or species with species_cutoffs). Flags are 0 or 1 (anything else is refused). */
typedef struct tricell_neighbor_options {
    double cutoff;    /* pairs with d < cutoff; finite and > 0 (0 with radii or species) */
    int half;         /* 1: each pair once (see the conventions) */
    int sorted;       /* 1: sorted by i, then j, then S; fills tricell_pairs.offsets */
    int grouped;      /* 1: grouped by i in the search's order (one counting pass); fills
                       * tricell_pairs.offsets. sorted implies it */
    int shifts;       /* store S (default 1) */
    int distances;    /* store d (default 1) */
    int vectors;      /* store D (default 0) */
    int threads;      /* threads for the search (default 1, 0 = all cores); same list */
    int backend;      /* a tricell_backend (default TRICELL_BACKEND_AUTOMATIC); same list */
    size_t max_pairs; /* refuse a list larger than this (default 5e8; 0 = no limit) */
    size_t max_bytes; /* refuse a list whose memory at its peak (docs/memory.md) passes this
                       * many bytes (default 3/4 of the memory the process may use; 0 = no limit) */
    /* Variable cutoffs (NULL: unused). radii: N per-atom radii, a pair counts when
     * d < radii[i] + radii[j]. species: N per-atom species, with species_cutoffs (a table of
     * species_cutoff_count entries): a pair counts when d < the table's cutoff for its two
     * species; a pair of species missing from the table never counts. The arrays are read
     * during tricell_neighbors() only. */
    const double* radii;
    const int32_t* species;
    const tricell_species_cutoff* species_cutoffs;
    size_t species_cutoff_count;
    /* Pairs of a subset (NULL: every point; an empty subset is a non-NULL query with
     * query_count 0). query: query_count indices of the positions, each < n and listed once. A full
     * list holds the (i, j, S) with i in the query; a half list each pair with both ends in it once
     * (canonical orientation) and each pair with one end in it once, oriented from that end. Every
     * point is a neighbour; read during the call only. */
    const uint32_t* query;
    size_t query_count;
    /* The k nearest within the cutoff (0: every pair). At most max_neighbors pairs per centre,
     * ranked by (d, j, S); the list comes grouped by i in that order, with offsets. Full lists
     * only (half and sorted must be 0). tie_tolerance (finite, >= 0): every other pair with
     * d <= d_k + tie_tolerance is kept too, d_k the centre's k-th distance. symmetric (0 or 1):
     * (j, i, -S) is kept wherever (i, j, S) is, so no edge is kept at one end only. */
    size_t max_neighbors;
    double tie_tolerance;
    int symmetric;
} tricell_neighbor_options;

TRICELL_C_API tricell_status tricell_neighbor_options_init(tricell_neighbor_options* options);

/* The search structure (grid, cell lists, stencil); reuse it to keep its buffers. */
typedef struct tricell_neighbor_search tricell_neighbor_search;
/* A stored list of pairs; reuse it to keep its buffers. */
typedef struct tricell_neighbor_list tricell_neighbor_list;

TRICELL_C_API tricell_status tricell_neighbor_search_create(tricell_neighbor_search** search);
TRICELL_C_API void tricell_neighbor_search_destroy(tricell_neighbor_search* search);
TRICELL_C_API tricell_status tricell_neighbor_list_create(tricell_neighbor_list** list);
TRICELL_C_API void tricell_neighbor_list_destroy(tricell_neighbor_list* list);

/* Finds the pairs of the n positions (3 n doubles; may be NULL when n == 0) and stores them
 * into list, replacing its contents. On failure the list is empty. */
TRICELL_C_API tricell_status tricell_neighbors(tricell_neighbor_search* search,
                                               const tricell_box* box, const double* positions,
                                               size_t n, const tricell_neighbor_options* options,
                                               tricell_neighbor_list* list);

/* A view of a stored list: pointers into its arrays (no copy), valid until the next call that
 * changes or destroys the list. A quantity that was not asked for is NULL. */
typedef struct tricell_pairs {
    size_t size;             /* number of pairs */
    const uint32_t* i;       /* size entries */
    const uint32_t* j;       /* size entries */
    const int32_t* shifts;   /* 3 per pair (Sa, Sb, Sc), or NULL */
    const double* distances; /* size entries, or NULL */
    const double* vectors;   /* 3 per pair (Dx, Dy, Dz), or NULL */
    size_t atoms;            /* N when offsets is set, else 0 */
    const size_t* offsets;   /* N + 1 entries: atom i's pairs are [offsets[i], offsets[i+1]) */
} tricell_pairs;

TRICELL_C_API tricell_status tricell_neighbor_list_pairs(const tricell_neighbor_list* list,
                                                         tricell_pairs* pairs);

/* ---- Verifying a list ------------------------------------------------------------------- */

/* The verdict of tricell_verify(): counts of each kind of difference and the first one in words
 * (truncated to the buffer). */
typedef struct tricell_verify_report {
    int ok;              /* 1: the list is right; 0: see message */
    size_t entries;      /* entries of the list examined */
    size_t expected;     /* pairs the reference found */
    size_t matched;      /* entries that matched a reference pair */
    size_t near_cutoff;  /* pairs within rounding of their cutoff, accepted either way */
    size_t missing;      /* reference pairs the list lacks */
    size_t extra;        /* listed pairs that are not pairs */
    size_t duplicates;   /* entries repeating a pair (in a half list: in either orientation) */
    size_t rule_breaks;  /* an index out of range, (i, i, 0), a shift along an open axis */
    size_t wrong_values; /* a listed d or D that differs from the one of the positions */
    char reference[32];  /* "brute force", "the dense backend" or "the hash backend" */
    char message[512];   /* "ok: ..." or the first difference, e.g. "pair (3, 17, [0 1 0]) at
                          * distance 2.31 < cutoff 2.5 is missing" */
} tricell_verify_report;

/* Checks the list `pairs` (tricell's own from tricell_neighbor_list_pairs(), or arrays of any
 * code filled in by hand: size, i, j, shifts, and optionally distances and vectors; offsets and
 * atoms are ignored) against an independent search of the n positions in box with options
 * (cutoff, or radii or species with species_cutoffs, and half say which list is expected;
 * threads, max_pairs and max_bytes bound the reference search; the other fields are ignored). A
 * full list must hold both orientations of every pair, a half list either orientation of each pair
 * exactly once. shifts may be NULL only when no axis is periodic. Returns TRICELL_OK whenever
 * the check ran, whatever its verdict (report->ok); an error status only for bad arguments (a
 * NULL pointer, a non-finite position, invalid options), with report untouched. */
TRICELL_C_API tricell_status tricell_verify(const tricell_box* box, const double* positions,
                                            size_t n, const tricell_neighbor_options* options,
                                            const tricell_pairs* pairs,
                                            tricell_verify_report* report);

/* ---- Batches of small structures ---------------------------------------------------------- */

/* One structure of a batch: its box and its n positions (3 n doubles; may be NULL when
 * n == 0). */
typedef struct tricell_structure {
    tricell_box box;
    const double* positions;
    size_t n;
} tricell_structure;

/* The lists of a batch; reuse it to keep its buffers (and one search object per thread). */
typedef struct tricell_batch_list tricell_batch_list;

TRICELL_C_API tricell_status tricell_batch_list_create(tricell_batch_list** list);
TRICELL_C_API void tricell_batch_list_destroy(tricell_batch_list* list);

/* The neighbour lists of count structures (structures may be NULL when count == 0), each with
 * its own box, periodicity and positions and one set of options for all: every structure gets
 * exactly the pairs, order and values tricell_neighbors() gives it alone, stored one structure
 * after the other in shared arrays. options.threads threads work across structures (0 = all
 * cores); the result does not depend on it. options.max_pairs and max_bytes bound the whole batch.
 * options.radii and options.species must be NULL (one cutoff, or one species table without
 * per-atom species, cannot serve structures of different sizes). On failure the list is empty
 * and the message names the lowest failing structure ("structure 17: position 3 is not finite
 * ..."). */
TRICELL_C_API tricell_status tricell_neighbors_batch(const tricell_structure* structures,
                                                     size_t count,
                                                     const tricell_neighbor_options* options,
                                                     tricell_batch_list* list);

/* How i and j of a batch number the atoms. */
typedef enum tricell_batch_indices {
    TRICELL_BATCH_LOCAL = 0, /* from 0 within each structure (as tricell_neighbors_batch) */
    TRICELL_BATCH_GLOBAL = 1 /* among all atoms of the batch in structure order: atom_offsets[s]
                              * + the local index, the index into the concatenated positions when
                              * the structures' positions lie one after another in one array
                              * (at most 2^32 - 1 atoms in all) */
} tricell_batch_indices;

/* tricell_neighbors_batch with the atoms numbered as `indices` (a tricell_batch_indices) says.
 * Concatenated positions (N_total x 3 with per-structure offsets, as machine-learning codes pass
 * a batch) need no copy: point each structure's positions into the one array and ask for
 * TRICELL_BATCH_GLOBAL. */
TRICELL_C_API tricell_status tricell_neighbors_batch_indexed(
    const tricell_structure* structures, size_t count, const tricell_neighbor_options* options,
    int indices, tricell_batch_list* list);

/* A view of a batch's lists (pointers into its arrays, no copy; valid until the next call that
 * changes or destroys the list). */
typedef struct tricell_batch_pairs {
    size_t structures;          /* count of the last call */
    const size_t* pair_offsets; /* structures + 1: structure s's pairs are
                                   [pair_offsets[s], pair_offsets[s + 1]) of `pairs` */
    const size_t* atom_offsets; /* structures + 1: structure s's atoms are numbered
                                   atom_offsets[s] .. atom_offsets[s + 1] - 1 among all atoms */
    tricell_pairs pairs;        /* every pair; i and j number the atoms of their own structure
                                   from 0 (or all atoms, TRICELL_BATCH_GLOBAL). With offsets
                                   (sorted, grouped, max_neighbors), pairs.atoms is the total
                                   atom count and atom a of structure s has the pairs
                                   [offsets[k], offsets[k + 1]) with k = atom_offsets[s] + a */
} tricell_batch_pairs;

TRICELL_C_API tricell_status tricell_batch_list_pairs(const tricell_batch_list* list,
                                                      tricell_batch_pairs* pairs);

/* ---- Verlet lists ----------------------------------------------------------------------- */

/* neighbors.cutoff is r_c; candidates are built at r_c + skin and refreshed by every update.
 * neighbors.sorted is ignored (the pairs are always grouped by i, with offsets); variable
 * cutoffs (radii, species) are not supported by the Verlet list. */
typedef struct tricell_verlet_options {
    tricell_neighbor_options neighbors;
    double skin; /* finite and >= 0 */
} tricell_verlet_options;

typedef struct tricell_verlet tricell_verlet;

TRICELL_C_API tricell_status tricell_verlet_options_init(tricell_verlet_options* options);
/* Validates the options. */
TRICELL_C_API tricell_status tricell_verlet_create(const tricell_verlet_options* options,
                                                   tricell_verlet** verlet);
TRICELL_C_API void tricell_verlet_destroy(tricell_verlet* verlet);
/* The pairs within r_c for these positions and box, rebuilding the candidates first when atoms
 * moved too far (or the atom count or periodicity changed). *rebuilt (if rebuilt is not NULL)
 * is set to 1 when it rebuilt, 0 otherwise. On failure the pairs are empty and the next update
 * rebuilds. */
TRICELL_C_API tricell_status tricell_verlet_update(tricell_verlet* verlet, const tricell_box* box,
                                                   const double* positions, size_t n, int* rebuilt);
/* The pairs of the last update, grouped by i (offsets set; order within an atom unspecified). */
TRICELL_C_API tricell_status tricell_verlet_pairs(const tricell_verlet* verlet,
                                                  tricell_pairs* pairs);

#ifdef __cplusplus
}
#endif

#endif /* TRICELL_H */
