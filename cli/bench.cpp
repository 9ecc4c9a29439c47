// tricell bench: times the neighbour-list call on a structure file, inside the process.
//
// The structure is read once; the list is computed once as a warm-up and then K times into the
// same reused NeighborList. Prints one "key value" line per measurement, for people and for
// benchmarks/compare: pairs, median and minimum seconds, pairs per second, the size of the
// stored arrays, the peak resident memory of the process and the distance tests per stored pair.
// --list-backends prints the names --backend takes, from the library's table of backends, so
// that compare needs no list of its own.
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

#include <tricell/error.hpp>
#include <tricell/neighbor_list.hpp>

#include "cli.hpp"

namespace tricell::cli {

namespace {

// The names --backend takes, from the library's table of backends (automatic first).
std::vector<std::string> backend_names() {
    std::vector<std::string> names;
    for (const SearchBackend backend : search_backends()) {
        names.push_back(backend_name(backend));
    }
    return names;
}

// Peak resident memory of this process image. VmHWM from /proc is reset by exec; getrusage's
// ru_maxrss is not (it would report a large parent's memory after fork + exec), so it is only
// the fallback where /proc is missing.
double peak_rss_mb() {
    if (std::FILE* status = std::fopen("/proc/self/status", "r")) {
        char line[256];
        double kilobytes = -1;
        while (std::fgets(line, sizeof line, status) != nullptr) {
            if (std::sscanf(line, "VmHWM: %lf kB", &kilobytes) == 1) {
                break;
            }
        }
        std::fclose(status);
        if (kilobytes >= 0) {
            return kilobytes / 1024.0;
        }
    }
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return double(usage.ru_maxrss) / 1024.0; // kilobytes on Linux
}

} // namespace

// The text of 'tricell bench --help', for the row of dispatch.cpp's table.
std::string bench_help() {
    std::vector<std::string> backends = backend_names();
    backends.front() += " (default)";
    return R"(usage: tricell bench FILE --cutoff R [--half] [--grouped | --sorted]
                     [--quantities ijSdD] [--repeat K] [--threads T] [--backend B]
                     [--max-pairs N] [--max-bytes N] [--input-format cif|xyz|poscar]
       tricell bench --list-backends

Times tricell's neighbour list of FILE: one warm-up call, then K timed calls (default 10) into
a reused list. Prints the order (search, grouped or sorted), pairs, median_s, min_s,
pairs_per_s, list_bytes and list_mb (the stored arrays, offsets included), base_rss_mb
(resident memory after reading FILE, before any search), peak_rss_mb (peak resident memory of
the whole process), the backend that ran, the cells it stored and tests_per_pair (the distance
tests the search makes per stored pair: what its stencil and clusters leave to test), one "key
value" per line.

Options:
  --cutoff R          cutoff, R > 0 (required)
  --half              half list (each pair once)
  --grouped           pairs grouped by i with per-atom offsets, in the search's order
  --sorted            pairs sorted by i, then j, then S, with per-atom offsets
  --quantities Q      what to store besides i and j: any of S (shifts), d (distances),
                      D (vectors); default "ijSd"
  --repeat K          timed calls, K >= 1 (default 10)
  --threads T         threads, T >= 0, 0 = all hardware threads (default 1)
  --backend B         )" +
           wrap(choices(backends), 22, 22) + R"(
  --list-backends     print the names --backend takes, one per line, and nothing else
  --max-pairs N       refuse lists of more than N pairs before allocating them (default
                      500000000; 0 = no limit)
  --max-bytes N       refuse lists whose memory would pass N bytes (a suffix K, M, G or T
                      counts powers of 1024: 16G) before allocating them (default three
                      quarters of the memory tricell may use; 0 = no limit)
  --input-format F    cif, xyz or poscar, instead of the guess from the file name
  -h, --help          this help
)";
}

int run_bench(Arguments& arguments) {
    std::string file;
    bool have_cutoff = false;
    long repeat = 10;
    io::ReadOptions read_options;
    NeighborOptions options;
    while (arguments.next()) {
        if (arguments.printed_help()) {
            return 0;
        } else if (arguments.flag("--list-backends")) {
            for (const std::string& name : backend_names()) {
                std::printf("%s\n", name.c_str());
            }
            return 0;
        } else if (arguments.option("--cutoff")) {
            options.cutoff = arguments.real();
            have_cutoff = true;
        } else if (arguments.flag("--half")) {
            options.half = true;
        } else if (arguments.flag("--grouped")) {
            options.grouped = true;
        } else if (arguments.flag("--sorted")) {
            options.sorted = true;
        } else if (arguments.option("--quantities")) {
            const std::string& q = arguments.value();
            if (q.find_first_not_of("ijSdD") != std::string::npos) {
                arguments.fail("--quantities takes letters of ijSdD, got '" + q + "'");
            }
            options.quantities.shifts = q.find('S') != std::string::npos;
            options.quantities.distances = q.find('d') != std::string::npos;
            options.quantities.vectors = q.find('D') != std::string::npos;
        } else if (arguments.option("--repeat")) {
            repeat = long(arguments.whole(1, 1000000));
        } else if (take_threads(arguments, options.threads)) {
        } else if (take_max_pairs(arguments, options.max_pairs)) {
        } else if (take_max_bytes(arguments, options.max_bytes)) {
        } else if (arguments.option("--backend")) {
            const std::string name = arguments.value();
            try {
                options.backend = parse_backend(name);
            } catch (const InvalidArgument& e) {
                arguments.fail(std::string("--backend: ") + e.what());
            }
        } else if (!take_input(arguments, read_options, file)) {
            arguments.unknown();
        }
    }
    require_file(arguments, file);
    if (!have_cutoff) {
        arguments.fail("missing --cutoff R");
    }
    if (options.grouped && options.sorted) {
        arguments.fail("--grouped and --sorted exclude each other (sorted output is grouped too)");
    }
    options.validate();

    const io::Structure structure = io::read_structure(file, read_options);
    const double base_rss = peak_rss_mb();
    NeighborList list;
    compute_neighbors(structure.box, structure.positions, options, list); // warm-up
    std::vector<double> seconds;
    for (long k = 0; k < repeat; ++k) {
        const auto start = std::chrono::steady_clock::now();
        compute_neighbors(structure.box, structure.positions, options, list);
        const auto stop = std::chrono::steady_clock::now();
        seconds.push_back(std::chrono::duration<double>(stop - start).count());
    }
    std::sort(seconds.begin(), seconds.end());
    const double median = seconds[seconds.size() / 2];
    const double list_bytes =
        double(list.i().size() + list.j().size()) * sizeof(std::uint32_t) +
        double(list.shifts().size()) * sizeof(std::int32_t) +
        double(list.distances().size() + list.vectors().size()) * sizeof(double) +
        double(list.offsets().size()) * sizeof(std::size_t);
    std::printf("file %s\n", file.c_str());
    std::printf("atoms %zu\n", structure.size());
    std::printf("cutoff %s\n", brief(options.cutoff).c_str());
    std::printf("half %d\n", options.half ? 1 : 0);
    std::printf("order %s\n", options.sorted ? "sorted" : options.grouped ? "grouped" : "search");
    std::printf("threads %d\n", options.threads);
    std::printf("pairs %zu\n", list.size());
    std::printf("median_s %.6g\n", median);
    std::printf("min_s %.6g\n", seconds.front());
    std::printf("pairs_per_s %.6g\n", double(list.size()) / median);
    std::printf("list_bytes %.0f\n", list_bytes);
    std::printf("list_mb %.3f\n", list_bytes / (1024.0 * 1024.0));
    std::printf("base_rss_mb %.3f\n", base_rss);
    std::printf("peak_rss_mb %.3f\n", peak_rss_mb());
    NeighborSearch search;
    search.build(structure.box, structure.positions, options);
    const SearchInfo info = search.info();
    std::printf("backend %s\n", backend_name(info.backend));
    std::printf("stored_cells %zu\n", info.stored_cells);
    const UnitWork work = search.unit_work();
    double tests = 0;
    for (const double unit : work.measured) {
        tests += unit;
    }
    std::printf("tests_per_pair %.4g\n", list.size() > 0 ? tests / double(list.size()) : 0.0);
    return 0;
}

} // namespace tricell::cli
