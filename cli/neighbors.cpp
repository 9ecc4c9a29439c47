// tricell neighbors: the neighbour list of a structure file (all pairs within a cutoff, or the
// k nearest of every atom), as TSV, CSV or JSON.
#include <cstdio>
#include <string>

#include <tricell/analysis/nearest.hpp>
#include <tricell/error.hpp>
#include <tricell/neighbor_list.hpp>
#include <tricell/verify.hpp>

#include "cli.hpp"
#include "pair_table.hpp"
#include "progress.hpp"
#include "text.hpp"

namespace tricell::cli {

// The text of 'tricell neighbors --help', for the row of dispatch.cpp's table.
std::string neighbors_help() {
    return R"(usage: tricell neighbors FILE --cutoff R [--half] [--sorted] [--format tsv|csv|json]
                         [--output PATH] [--max-pairs N] [--max-bytes N] [--threads T]
                         [--verify] [--quiet] [--input-format cif|xyz|poscar]
       tricell neighbors FILE --nearest K [--format tsv|csv|json] [--output PATH]
                         [--max-pairs N] [--threads T] [--quiet]
                         [--input-format cif|xyz|poscar]

Lists every pair (i, j, S) of atoms closer than R: D = x_j - x_i + H S with |D| < R, where x
are the positions in the order the file gives them (for a CIF, the symmetry-expanded unit
cell), H has the lattice vectors a, b, c as columns and S = (Sa, Sb, Sc) is the image shift
(0 along non-periodic axes). Indices are 0-based. An atom paired with its own periodic image is
listed; an atom with itself is not.

With --nearest K instead of --cutoff, lists the K nearest (j, S) of every atom, periodic images
included (K may exceed the number of atoms), nearest first, ties broken by j and then S, so
the output is the same on every run.

Options:
  --cutoff R          cutoff in the length unit of the file (Angstrom), R > 0
  --nearest K         the K nearest neighbours of every atom instead of a cutoff, K >= 1
  --half              each pair once, oriented i < j (for i == j: S lexicographically positive)
  --sorted            sort by i, then j, then Sa, Sb, Sc (otherwise the order is unspecified)
  --format F          tsv (default), csv or json
  --output PATH       write to PATH, completely or not at all, instead of standard output
  --max-pairs N       refuse lists of more than N pairs before allocating them (default
                      500000000, about 14 GB; 0 = no limit); with --nearest, refuse K times
                      the number of atoms above N
  --max-bytes N       refuse lists whose memory would pass N bytes (a suffix K, M, G or T
                      counts powers of 1024: 16G) before allocating them (default three
                      quarters of the memory tricell may use; 0 = no limit)
  --threads T         threads of the search and of the formatting of the table, 0 = all
                      hardware threads (default 1); the output is the same for any T
  --verify            after writing the list, check it against an independent search (brute
                      force, or another backend for large systems) and the list rules; prints
                      'tricell: verify: ok: ...' or 'tricell: verify: FAILED: <the first
                      difference>' on stderr and exits with status 3 on a mismatch
  --quiet             no progress on stderr (shown only when stderr is a terminal)
  --input-format F    cif, xyz or poscar, instead of the guess from the file name
  -h, --help          this help

Output: tsv prints a first line '# i j Sa Sb Sc d Dx Dy Dz' and then one tab-separated line per
pair; csv prints the header 'i,j,Sa,Sb,Sc,d,Dx,Dy,Dz' and comma-separated lines; json prints
one object {"file", "atoms", "cutoff", "half", "pairs", "i", "j", "S", "d", "D"} with one array
per column (S and D as arrays of triples). With --nearest the columns are i j Sa Sb Sc d (K
rows per atom, atom by atom) and json has "k" instead of "cutoff" and "half". Reals are written in the shortest form that reads
back as the same double (at most 17 significant digits).
)";
}

int run_neighbors(Arguments& arguments) {
    std::string file;
    std::string output;
    bool have_cutoff = false;
    std::size_t nearest = 0;
    bool quiet = false;
    bool verify_list = false;
    TableFormat format = TableFormat::tsv;
    io::ReadOptions read_options;
    NeighborOptions options;
    options.quantities.shifts = true;
    options.quantities.distances = true;
    options.quantities.vectors = true;
    while (arguments.next()) {
        if (arguments.printed_help()) {
            return 0;
        }
        if (arguments.option("--cutoff")) {
            options.cutoff = arguments.real();
            have_cutoff = true;
        } else if (arguments.option("--nearest")) {
            nearest = arguments.whole(1, std::size_t(1) << 31);
        } else if (arguments.flag("--half")) {
            options.half = true;
        } else if (arguments.flag("--sorted")) {
            options.sorted = true;
        } else if (arguments.flag("--verify")) {
            verify_list = true;
        } else if (take_format(arguments, format)) {
        } else if (take_quiet(arguments, quiet)) {
        } else if (arguments.option("--output")) {
            output = arguments.value();
        } else if (take_max_pairs(arguments, options.max_pairs)) {
        } else if (take_max_bytes(arguments, options.max_bytes)) {
        } else if (take_threads(arguments, options.threads)) {
        } else if (!take_input(arguments, read_options, file)) {
            arguments.unknown();
        }
    }
    require_file(arguments, file);
    if (nearest > 0) {
        if (have_cutoff || options.half || options.sorted || verify_list) {
            arguments.fail("--nearest takes no --cutoff, --half, --sorted or --verify");
        }
    } else if (!have_cutoff) {
        arguments.fail("missing --cutoff R or --nearest K");
    }
    // Progress only when the table goes to a file: on a terminal it would mix with the rows.
    const bool show_progress = !quiet && !(output.empty() && stdout_is_terminal());
    const io::Structure structure = io::read_structure(file, read_options);
    if (nearest > 0) {
        const std::size_t atoms = structure.size();
        if (options.max_pairs != 0 && atoms > 0 && nearest > options.max_pairs / atoms) {
            throw InvalidArgument("--nearest " + std::to_string(nearest) + " for " +
                                  std::to_string(atoms) + " atoms lists more than --max-pairs " +
                                  std::to_string(options.max_pairs) +
                                  " neighbours; raise --max-pairs to allow it (0 = no limit)");
        }
        NearestOptions nearest_options;
        nearest_options.threads = options.threads;
        const NearestNeighbors result =
            nearest_neighbors(structure.box, structure.positions, nearest, nearest_options);
        write_text(output, [&](TextSink& sink) {
            write_nearest(sink, result, format, file, options.threads, show_progress);
        });
        return 0;
    }
    // compute_neighbors() validates the options (cutoff > 0) before any work.
    const NeighborList list = compute_neighbors(structure.box, structure.positions, options);

    const PairTableHeader header{file, structure.size(), options.cutoff, options.half};
    write_text(output, [&](TextSink& sink) {
        write_pairs(sink, list, format, header, options.threads, show_progress);
    });
    if (verify_list) {
        const VerifyReport report = verify(structure.box, structure.positions, options, list);
        std::fprintf(stderr, "tricell: verify: %s%s\n",
                     report.ok ? "" : "FAILED: ", report.message.c_str());
        return report.ok ? 0 : verify_failed;
    }
    return 0;
}

} // namespace tricell::cli
