// Rate of `tricell neighbors` text output: the writer of the command (cli/pair_table,
// std::to_chars into a reused buffer, on 1 and 2 threads as --threads sets) against the writer it
// replaced (snprintf "%.17g" per line and one std::string per JSON item, kept here verbatim as the
// baseline), both writing a file through the command's all-or-nothing Output, interleaved in the
// same run, median of the repeats, wall clock and the process's CPU time (all threads: the work,
// not the wait). A plain timing program, not a test:
//
//   taskset -c 0 build/benchmarks/output_bench [--repeat K] [--dir DIR] [FILE CUTOFF]
//
// Without FILE it writes the full list of 20000 random atoms in a 58.5 Å cube at 6.8 Å (about
// 2.6 M pairs with 17-digit reals, the worst case for the text). Prints M pairs/s per writer.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include <time.h>

#include <tricell/io/io.hpp>
#include <tricell/neighbor_list.hpp>

#include "cli.hpp"
#include "pair_table.hpp"
#include "text.hpp"

namespace {

using tricell::NeighborList;
using tricell::cli::Output;

// ---- an snprintf writer (baseline) ---------------------------------------------------------

std::string legacy_exact(double value) {
    char text[32];
    std::snprintf(text, sizeof text, "%.17g", value);
    return text;
}

void legacy_table(Output& out, const NeighborList& list, char separator, bool comment_header) {
    const char s = separator;
    std::string buffer =
        comment_header ? "# i j Sa Sb Sc d Dx Dy Dz\n" : "i,j,Sa,Sb,Sc,d,Dx,Dy,Dz\n";
    char line[256];
    for (std::size_t k = 0; k < list.size(); ++k) {
        const tricell::Shift shift = list.shift(k);
        const Eigen::Vector3d d = list.vector(k);
        std::snprintf(line, sizeof line, "%u%c%u%c%d%c%d%c%d%c%.17g%c%.17g%c%.17g%c%.17g\n",
                      list.i()[k], s, list.j()[k], s, shift[0], s, shift[1], s, shift[2], s,
                      list.distances()[k], s, d[0], s, d[1], s, d[2]);
        buffer += line;
        if (buffer.size() > (1U << 16)) {
            out.write(buffer);
            buffer.clear();
        }
    }
    out.write(buffer);
}

void legacy_json(Output& out, const NeighborList& list, std::size_t atoms, double cutoff) {
    std::string buffer = "{\n  \"file\": \"x\",\n  \"atoms\": " + std::to_string(atoms) +
                         ",\n  \"cutoff\": " + legacy_exact(cutoff) +
                         ",\n  \"half\": false,\n  \"pairs\": " + std::to_string(list.size());
    const auto flush = [&] {
        if (buffer.size() > (1U << 16)) {
            out.write(buffer);
            buffer.clear();
        }
    };
    const auto array = [&](const char* key, auto&& item) {
        buffer += ",\n  \"";
        buffer += key;
        buffer += "\": [";
        for (std::size_t k = 0; k < list.size(); ++k) {
            buffer += k == 0 ? "" : ", ";
            buffer += item(k);
            flush();
        }
        buffer += "]";
    };
    array("i", [&](std::size_t k) { return std::to_string(list.i()[k]); });
    array("j", [&](std::size_t k) { return std::to_string(list.j()[k]); });
    array("S", [&](std::size_t k) {
        const tricell::Shift shift = list.shift(k);
        return "[" + std::to_string(shift[0]) + ", " + std::to_string(shift[1]) + ", " +
               std::to_string(shift[2]) + "]";
    });
    array("d", [&](std::size_t k) { return legacy_exact(list.distances()[k]); });
    array("D", [&](std::size_t k) {
        const Eigen::Vector3d d = list.vector(k);
        return "[" + legacy_exact(d[0]) + ", " + legacy_exact(d[1]) + ", " + legacy_exact(d[2]) +
               "]";
    });
    buffer += "\n}\n";
    out.write(buffer);
}

// ---- the run ------------------------------------------------------------------------------

struct Writer {
    const char* name;
    bool legacy;
    tricell::cli::TableFormat format;
    int threads;
    std::vector<double> seconds;     // wall clock
    std::vector<double> cpu_seconds; // this process, user + system (less noisy on a busy machine)
};

double cpu_now() {
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

double median(std::vector<double> x) {
    std::sort(x.begin(), x.end());
    return x[x.size() / 2];
}

} // namespace

int main(int argc, char** argv) {
    int repeat = 5;
    std::string dir = "/tmp";
    std::vector<std::string> positional;
    for (int a = 1; a < argc; ++a) {
        const std::string arg = argv[a];
        if (arg == "--repeat" && a + 1 < argc) {
            repeat = std::max(1, std::atoi(argv[++a]));
        } else if (arg == "--dir" && a + 1 < argc) {
            dir = argv[++a];
        } else {
            positional.push_back(arg);
        }
    }
    tricell::Box box = tricell::Box::from_parameters(58.5, 58.5, 58.5, 90, 90, 90);
    std::vector<Eigen::Vector3d> x;
    tricell::NeighborOptions options;
    options.cutoff = 6.8;
    if (positional.size() == 2) {
        const tricell::io::Structure s = tricell::io::read_structure(positional[0]);
        box = s.box;
        x = s.positions;
        options.cutoff = std::atof(positional[1].c_str());
    } else if (positional.empty()) {
        std::mt19937_64 random(15);
        std::uniform_real_distribution<double> u(0, 58.5);
        for (int k = 0; k < 20000; ++k) {
            x.emplace_back(u(random), u(random), u(random));
        }
    } else {
        std::fprintf(stderr, "usage: output_bench [--repeat K] [--dir DIR] [FILE CUTOFF]\n");
        return 2;
    }
    options.quantities.vectors = true;
    const NeighborList list = tricell::compute_neighbors(box, x, options);
    const tricell::cli::PairTableHeader header{"x", x.size(), options.cutoff, false};
    using tricell::cli::TableFormat;
    std::vector<Writer> writers = {
        {"tsv snprintf (before)", true, TableFormat::tsv, 1, {}, {}},
        {"tsv to_chars", false, TableFormat::tsv, 1, {}, {}},
        {"tsv to_chars, 2 threads", false, TableFormat::tsv, 2, {}, {}},
        {"csv snprintf (before)", true, TableFormat::csv, 1, {}, {}},
        {"csv to_chars", false, TableFormat::csv, 1, {}, {}},
        {"csv to_chars, 2 threads", false, TableFormat::csv, 2, {}, {}},
        {"json std::string (before)", true, TableFormat::json, 1, {}, {}},
        {"json to_chars", false, TableFormat::json, 1, {}, {}},
        {"json to_chars, 2 threads", false, TableFormat::json, 2, {}, {}},
    };
    const std::string path = dir + "/tricell-output-bench.txt";
    for (int r = 0; r < repeat; ++r) {
        for (Writer& w : writers) {
            const auto start = std::chrono::steady_clock::now();
            const double cpu_start = cpu_now();
            Output out(path);
            if (!w.legacy) {
                tricell::cli::TextSink sink(out);
                tricell::cli::write_pairs(sink, list, w.format, header, w.threads, false);
                sink.flush();
            } else if (w.format == TableFormat::json) {
                legacy_json(out, list, x.size(), options.cutoff);
            } else {
                legacy_table(out, list, w.format == TableFormat::tsv ? '\t' : ',',
                             w.format == TableFormat::tsv);
            }
            out.commit();
            w.cpu_seconds.push_back(cpu_now() - cpu_start);
            w.seconds.push_back(
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
        }
    }
    std::remove(path.c_str());
    std::printf("%zu atoms, %zu pairs, cutoff %g, %d repeats, into %s\n", x.size(), list.size(),
                options.cutoff, repeat, path.c_str());
    std::printf("%-28s %10s %10s %14s %14s\n", "writer", "wall s", "cpu s", "M pairs/s",
                "M pairs/cpu s");
    for (const Writer& w : writers) {
        const double t = median(w.seconds), c = median(w.cpu_seconds);
        std::printf("%-28s %10.3f %10.3f %14.2f %14.2f\n", w.name, t, c,
                    double(list.size()) / t / 1e6, double(list.size()) / c / 1e6);
    }
    return 0;
}
