// tricell rdf: the radial distribution function g(r) and the running coordination number n(r),
// total and for pairs of species, averaged over every frame of a file (tricell::Rdf, read frame
// by frame with io::FrameReader), as a table and optionally a plot.
#include <cstdio>
#include <map>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <tricell/analysis/rdf.hpp>
#include <tricell/error.hpp>
#include <tricell/io/trajectory.hpp>
#include <tricell/neighbor_list.hpp>

#include "cli.hpp"
#include "pair_table.hpp"
#include "plot.hpp"
#include "progress.hpp"
#include "text.hpp"

namespace tricell::cli {

// The text of 'tricell rdf --help', for the row of dispatch.cpp's table.
std::string rdf_help() {
    return R"(usage: tricell rdf FILE --rmax R --bins N [--pair A-B ...] [--plot PATH.svg|PATH.png]
                   [--format tsv|csv|json] [--output PATH] [--threads T] [--max-pairs N]
                   [--quiet] [--input-format cif|xyz|poscar]

The radial distribution function g(r) over every periodic image (R may exceed the cell),
averaged over every frame of FILE: each frame of a multi-frame extended XYZ trajectory is read
and added in turn, in constant memory; a CIF or POSCAR is one frame. Every axis must be
periodic. Bin k covers [k R/N, (k+1) R/N) and is normalised by its exact shell volume, as
ASE's get_rdf and freud do: g(r) = pairs / (N_atoms * (N_atoms / V) * shell volume). The
running coordination number n(r) is the mean number of neighbours within the upper edge of
the bin. A pair A-B gives g_AB(r), normalised by N_A * (N_B / V) (ASE's elements=(A, B) uses
N_A * (N / V): its value is ours times N_B / N), and n_AB(r), the mean number of B atoms
within r of an A atom.

Options:
  --rmax R            largest distance, R > 0 (required)
  --bins N            number of bins (required)
  --pair A-B          also the partial g and n of the species A and B as written in the
                      file (repeatable), e.g. --pair O-H
  --plot PATH         draw g(r) (total and partials) into PATH, an SVG (*.svg) or PNG (*.png)
                      image, completely or not at all
  --format F          tsv (default), csv or json
  --output PATH       write to PATH, completely or not at all, instead of standard output
  --threads T         threads of each frame's search, 0 = all hardware threads (default 1)
  --max-pairs N       refuse a frame whose pairs within R (each pair once) would be more than
                      N, before searching it (default 500000000; 0 = no limit): the work
                      grows with the pairs, though none are stored
  --quiet             no progress on stderr (shown only when stderr is a terminal)
  --input-format F    cif, xyz or poscar, instead of the guess from the file name
  -h, --help          this help

Output: tsv prints a first line '# r g n' followed by 'g_A-B n_A-B' for each --pair, then
one tab-separated line per bin (r is the bin centre); csv prints the same columns with a header
line 'r,g,n,...' and commas; json prints one object {"file", "frames", "rmax", "bins", "r",
"g", "n", "pairs"} where "pairs" holds {"a", "b", "g", "n"} for each --pair. Reals are the
shortest text that reads back as the same double.
)";
}

namespace {

struct PairName {
    std::string a, b;
    std::string name() const { return a + "-" + b; }
};

PairName parse_pair(const Arguments& arguments, const std::string& text) {
    const std::size_t dash = text.find('-');
    if (dash == std::string::npos || dash == 0 || dash + 1 >= text.size() ||
        text.find('-', dash + 1) != std::string::npos) {
        arguments.fail("--pair expects two species A-B such as O-H, got '" + text + "'");
    }
    return PairName{text.substr(0, dash), text.substr(dash + 1)};
}

// Species names to the integers tricell::Rdf counts, numbered in order of first appearance over
// all frames so that a name keeps its number from frame to frame.
class SpeciesNumbers {
  public:
    std::vector<std::int32_t> of(const std::vector<std::string>& species) {
        std::vector<std::int32_t> out(species.size());
        for (std::size_t k = 0; k < species.size(); ++k) {
            const auto [at, added] = numbers_.emplace(species[k], std::int32_t(names_.size()));
            if (added) {
                names_.push_back(species[k]);
            }
            out[k] = at->second;
        }
        return out;
    }
    /// The number of `name`; InvalidArgument naming the pair and the species seen otherwise.
    std::int32_t find(const std::string& name, const PairName& pair,
                      const std::string& file) const {
        const auto at = numbers_.find(name);
        if (at == numbers_.end()) {
            std::string seen;
            for (const std::string& n : names_) {
                seen += (seen.empty() ? "" : ", ") + n;
            }
            throw InvalidArgument("--pair " + pair.name() + ": no atom of species '" + name +
                                  "' in " + file + " (species: " + seen + ")");
        }
        return at->second;
    }

  private:
    std::map<std::string, std::int32_t> numbers_;
    std::vector<std::string> names_;
};

struct Column {
    std::string label; // "total" or "A-B"
    RdfCurve curve;
};

void write_table(TextSink& sink, const std::vector<Column>& columns, TableFormat format) {
    const char separator = format == TableFormat::csv ? ',' : '\t';
    sink.put(format == TableFormat::csv ? "r,g,n" : "# r g n");
    for (std::size_t c = 1; c < columns.size(); ++c) {
        const std::string& label = columns[c].label;
        sink.put(format == TableFormat::csv ? ",g_" : " g_");
        sink.put(label);
        sink.put(format == TableFormat::csv ? ",n_" : " n_");
        sink.put(label);
    }
    sink.put('\n');
    const std::vector<double>& r = columns.front().curve.r;
    for (std::size_t k = 0; k < r.size(); ++k) {
        sink.put_real(r[k]);
        for (const Column& column : columns) {
            sink.put(separator);
            sink.put_real(column.curve.g[k]);
            sink.put(separator);
            sink.put_real(column.curve.n[k]);
        }
        sink.put('\n');
    }
}

void json_reals(TextSink& sink, const std::vector<double>& values) {
    sink.put('[');
    for (std::size_t k = 0; k < values.size(); ++k) {
        if (k > 0) {
            sink.put(", ");
        }
        sink.put_real(values[k]);
    }
    sink.put(']');
}

void write_json(TextSink& sink, const std::vector<Column>& columns,
                const std::vector<PairName>& pairs, const std::string& file, const Rdf& rdf) {
    sink.put("{\n  \"file\": ");
    sink.put(json_string(file));
    sink.put(",\n  \"frames\": ");
    sink.put_integer(rdf.frames());
    sink.put(",\n  \"rmax\": ");
    sink.put_real(rdf.options().rmax);
    sink.put(",\n  \"bins\": ");
    sink.put_integer(rdf.options().bins);
    sink.put(",\n  \"r\": ");
    json_reals(sink, columns.front().curve.r);
    sink.put(",\n  \"g\": ");
    json_reals(sink, columns.front().curve.g);
    sink.put(",\n  \"n\": ");
    json_reals(sink, columns.front().curve.n);
    sink.put(",\n  \"pairs\": [");
    for (std::size_t p = 0; p < pairs.size(); ++p) {
        sink.put(p == 0 ? "\n    {\"a\": " : ",\n    {\"a\": ");
        sink.put(json_string(pairs[p].a));
        sink.put(", \"b\": ");
        sink.put(json_string(pairs[p].b));
        sink.put(", \"g\": ");
        json_reals(sink, columns[p + 1].curve.g);
        sink.put(", \"n\": ");
        json_reals(sink, columns[p + 1].curve.n);
        sink.put('}');
    }
    sink.put(pairs.empty() ? "]\n}\n" : "\n  ]\n}\n");
}

// Refuses a frame with more than max_pairs pairs within rmax (each pair once) before it is
// searched, with the estimate NeighborSearch::build() makes from the density.
void check_pair_limit(const io::Structure& frame, double rmax, std::size_t max_pairs) {
    if (max_pairs == 0) {
        return;
    }
    NeighborOptions options;
    options.cutoff = rmax;
    options.half = true;
    options.max_pairs = max_pairs;
    NeighborSearch().build(frame.box, frame.positions, options);
}

Plot rdf_plot(const std::string& file, const std::vector<Column>& columns, std::size_t frames) {
    Plot plot;
    plot.title =
        "g(r), " + file + " (" + std::to_string(frames) + (frames == 1 ? " frame)" : " frames)");
    plot.x_label = "r";
    plot.y_label = "g(r)";
    for (const Column& column : columns) {
        plot.series.push_back(Series{column.label, column.curve.r, column.curve.g});
    }
    return plot;
}

} // namespace

int run_rdf(Arguments& arguments) {
    std::string file;
    std::string output;
    std::string plot_path;
    bool have_rmax = false;
    bool have_bins = false;
    bool quiet = false;
    std::size_t max_pairs = NeighborOptions().max_pairs;
    TableFormat format = TableFormat::tsv;
    std::vector<PairName> pairs;
    io::ReadOptions read_options;
    RdfOptions options;
    while (arguments.next()) {
        if (arguments.printed_help()) {
            return 0;
        }
        if (arguments.option("--rmax")) {
            options.rmax = arguments.real();
            have_rmax = true;
        } else if (arguments.option("--bins")) {
            options.bins = arguments.whole(1, RdfOptions::max_bins);
            have_bins = true;
        } else if (arguments.option("--pair")) {
            pairs.push_back(parse_pair(arguments, arguments.value()));
        } else if (take_plot(arguments, plot_path)) {
        } else if (take_format(arguments, format)) {
        } else if (arguments.option("--output")) {
            output = arguments.value();
        } else if (take_threads(arguments, options.threads)) {
        } else if (take_max_pairs(arguments, max_pairs)) {
        } else if (take_quiet(arguments, quiet)) {
        } else if (!take_input(arguments, read_options, file)) {
            arguments.unknown();
        }
    }
    require_file(arguments, file);
    if (!have_rmax) {
        arguments.fail("missing --rmax R");
    }
    if (!have_bins) {
        arguments.fail("missing --bins N");
    }
    // The command's own check of --rmax, in its words; Rdf checks the rest before any file is
    // read (--bins and --threads are already in range).
    if (!(options.rmax > 0)) {
        std::ostringstream got;
        got.precision(12);
        got << options.rmax;
        throw InvalidArgument("--rmax must be finite and > 0 (got " + got.str() + ")");
    }
    Rdf rdf(options);

    io::FrameReader reader(file, read_options);
    SpeciesNumbers numbers;
    io::Structure frame;
    Progress progress("frames", 0, !quiet);
    while (reader.next(frame)) {
        // The library's message says what is wrong with a frame; say which frame it is.
        const std::string where = file + " (frame " + std::to_string(rdf.frames()) + "): ";
        try {
            check_pair_limit(frame, options.rmax, max_pairs);
            rdf.add_frame(frame.box, frame.positions, numbers.of(frame.species));
        } catch (const GeometryError& e) {
            throw GeometryError(where + e.what());
        } catch (const PairLimitError& e) {
            throw e.with_subject(where + e.subject());
        } catch (const InvalidArgument& e) {
            throw InvalidArgument(where + e.what());
        }
        progress.step(rdf.frames());
    }
    progress.finish();
    if (rdf.frames() == 0) {
        throw InvalidArgument(file + ": no frame to average");
    }
    std::vector<Column> columns{{"total", rdf.total()}};
    for (const PairName& pair : pairs) {
        columns.push_back(Column{pair.name(), rdf.partial(numbers.find(pair.a, pair, file),
                                                          numbers.find(pair.b, pair, file))});
    }

    if (!plot_path.empty()) {
        write_plot(rdf_plot(file, columns, rdf.frames()), plot_path);
    }
    write_text(output, [&](TextSink& sink) {
        if (format == TableFormat::json) {
            write_json(sink, columns, pairs, file, rdf);
        } else {
            write_table(sink, columns, format);
        }
    });
    return 0;
}

} // namespace tricell::cli
