#include "pair_table.hpp"

#include "progress.hpp"
#include "text.hpp"

namespace tricell::cli {

namespace {

// Rows per block of the threaded formatting (text.hpp, write_blocks).
constexpr std::size_t block_rows = std::size_t(1) << 15;

// One pass over n items, formatted by format(TextSink&, begin, end) on `threads` threads, the
// pass being number `pass` of the passes progress counts (n items each).
template <class Format>
void pass(TextSink& sink, std::size_t n, int threads, Progress& progress, std::size_t number,
          Format&& format) {
    write_blocks(sink, n, threads, block_rows, format,
                 [&](std::size_t done) { progress.step(number * n + done); });
}

void write_rows(TextSink& sink, const NeighborList& list, char separator, int threads,
                Progress& progress) {
    const std::uint32_t* i = list.i().data();
    const std::uint32_t* j = list.j().data();
    const std::int32_t* s = list.shifts().data();
    const double* d = list.distances().data();
    const double* v = list.vectors().data();
    pass(sink, list.size(), threads, progress, 0,
         [=](TextSink& out, std::size_t begin, std::size_t end) {
             for (std::size_t k = begin; k < end; ++k) {
                 out.put_integer(i[k]);
                 out.put(separator);
                 out.put_integer(j[k]);
                 for (std::size_t c = 0; c < 3; ++c) {
                     out.put(separator);
                     out.put_integer(s[3 * k + c]);
                 }
                 out.put(separator);
                 out.put_real(d[k]);
                 for (std::size_t c = 0; c < 3; ++c) {
                     out.put(separator);
                     out.put_real(v[3 * k + c]);
                 }
                 out.put('\n');
             }
         });
}

void write_nearest_rows(TextSink& sink, const NearestNeighbors& nearest, char separator,
                        int threads, Progress& progress) {
    pass(sink, nearest.j.size(), threads, progress, 0,
         [&nearest, separator](TextSink& out, std::size_t begin, std::size_t end) {
             for (std::size_t e = begin; e < end; ++e) {
                 out.put_integer(e / nearest.k);
                 out.put(separator);
                 out.put_integer(nearest.j[e]);
                 for (std::size_t c = 0; c < 3; ++c) {
                     out.put(separator);
                     out.put_integer(nearest.shifts[3 * e + c]);
                 }
                 out.put(separator);
                 out.put_real(nearest.distances[e]);
                 out.put('\n');
             }
         });
}

void put_number(TextSink& sink, std::int32_t x) {
    sink.put_integer(x);
}
void put_number(TextSink& sink, std::uint32_t x) {
    sink.put_integer(x);
}
void put_number(TextSink& sink, double x) {
    sink.put_real(x);
}

// The JSON arrays of a table: ", "-separated items, a number or a triple "[a, b, c]" each.
struct JsonArrays {
    TextSink& sink;
    std::size_t n;
    int threads;
    Progress& progress;
    std::size_t passes = 0;

    template <class Item> void array(const char* key, Item&& item) {
        sink.put(",\n  \"");
        sink.put(key);
        sink.put("\": [");
        pass(sink, n, threads, progress, passes++,
             [&item](TextSink& out, std::size_t begin, std::size_t end) {
                 for (std::size_t k = begin; k < end; ++k) {
                     if (k > 0) {
                         out.put(", ");
                     }
                     item(out, k);
                 }
             });
        sink.put(']');
    }
    template <class T> void numbers(const char* key, const T* values) {
        array(key, [values](TextSink& out, std::size_t k) { put_number(out, values[k]); });
    }
    template <class T> void triples(const char* key, const T* values) {
        array(key, [values](TextSink& out, std::size_t k) {
            out.put('[');
            put_number(out, values[3 * k]);
            out.put(", ");
            put_number(out, values[3 * k + 1]);
            out.put(", ");
            put_number(out, values[3 * k + 2]);
            out.put(']');
        });
    }
};

void write_json(TextSink& sink, const NeighborList& list, const PairTableHeader& header,
                int threads, Progress& progress) {
    sink.put("{\n  \"file\": ");
    sink.put(json_string(header.file));
    sink.put(",\n  \"atoms\": ");
    sink.put_integer(header.atoms);
    sink.put(",\n  \"cutoff\": ");
    sink.put_real(header.cutoff);
    sink.put(",\n  \"half\": ");
    sink.put(header.half ? "true" : "false");
    sink.put(",\n  \"pairs\": ");
    sink.put_integer(list.size());
    JsonArrays json{sink, list.size(), threads, progress};
    json.numbers("i", list.i().data());
    json.numbers("j", list.j().data());
    json.triples("S", list.shifts().data());
    json.numbers("d", list.distances().data());
    json.triples("D", list.vectors().data());
    sink.put("\n}\n");
}

} // namespace

void write_nearest(TextSink& sink, const NearestNeighbors& nearest, TableFormat format,
                   const std::string& file, int threads, bool show_progress) {
    const std::size_t n = nearest.j.size();
    Progress progress("writing neighbours", format == TableFormat::json ? 4 * n : n, show_progress);
    switch (format) {
    case TableFormat::tsv:
        sink.put("# i j Sa Sb Sc d\n");
        write_nearest_rows(sink, nearest, '\t', threads, progress);
        break;
    case TableFormat::csv:
        sink.put("i,j,Sa,Sb,Sc,d\n");
        write_nearest_rows(sink, nearest, ',', threads, progress);
        break;
    case TableFormat::json:
        sink.put("{\n  \"file\": ");
        sink.put(json_string(file));
        sink.put(",\n  \"atoms\": ");
        sink.put_integer(nearest.size());
        sink.put(",\n  \"k\": ");
        sink.put_integer(nearest.k);
        sink.put(",\n  \"pairs\": ");
        sink.put_integer(n);
        {
            JsonArrays json{sink, n, threads, progress};
            json.array(
                "i", [&nearest](TextSink& out, std::size_t e) { out.put_integer(e / nearest.k); });
            json.numbers("j", nearest.j.data());
            json.triples("S", nearest.shifts.data());
            json.numbers("d", nearest.distances.data());
        }
        sink.put("\n}\n");
        break;
    }
}

void write_pairs(TextSink& sink, const NeighborList& list, TableFormat format,
                 const PairTableHeader& header, int threads, bool show_progress) {
    const std::size_t passes = format == TableFormat::json ? 5 : 1;
    Progress progress("writing pairs", passes * list.size(), show_progress);
    switch (format) {
    case TableFormat::tsv:
        sink.put("# i j Sa Sb Sc d Dx Dy Dz\n");
        write_rows(sink, list, '\t', threads, progress);
        break;
    case TableFormat::csv:
        sink.put("i,j,Sa,Sb,Sc,d,Dx,Dy,Dz\n");
        write_rows(sink, list, ',', threads, progress);
        break;
    case TableFormat::json:
        write_json(sink, list, header, threads, progress);
        break;
    }
}

} // namespace tricell::cli
