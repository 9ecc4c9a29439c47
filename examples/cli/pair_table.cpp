#include "pair_table.hpp"

#include "progress.hpp"
#include "text.hpp"

namespace tricell::cli {

namespace {

void write_rows(TextSink& sink, const NeighborList& list, char separator, Progress& progress) {
    const std::uint32_t* i = list.i().data();
    const std::uint32_t* j = list.j().data();
    const std::int32_t* s = list.shifts().data();
    const double* d = list.distances().data();
    const double* v = list.vectors().data();
    for (std::size_t k = 0; k < list.size(); ++k) {
        sink.put_integer(i[k]);
        sink.put(separator);
        sink.put_integer(j[k]);
        for (int c = 0; c < 3; ++c) {
            sink.put(separator);
            sink.put_integer(s[3 * k + std::size_t(c)]);
        }
        sink.put(separator);
        sink.put_real(d[k]);
        for (int c = 0; c < 3; ++c) {
            sink.put(separator);
            sink.put_real(v[3 * k + std::size_t(c)]);
        }
        sink.put('\n');
        progress.update(k);
    }
}

// ", "-separated items of one JSON array, item(k) writing item k.
template <class Item>
void json_array(TextSink& sink, const char* key, std::size_t size, Item&& item) {
    sink.put(",\n  \"");
    sink.put(key);
    sink.put("\": [");
    for (std::size_t k = 0; k < size; ++k) {
        if (k > 0) {
            sink.put(", ");
        }
        item(k);
    }
    sink.put(']');
}

void put_number(TextSink& sink, std::int32_t x) {
    sink.put_integer(x);
}
void put_number(TextSink& sink, double x) {
    sink.put_real(x);
}

// "[a, b, c]" of three numbers.
template <class T> void json_triple(TextSink& sink, const T* values) {
    sink.put('[');
    put_number(sink, values[0]);
    sink.put(", ");
    put_number(sink, values[1]);
    sink.put(", ");
    put_number(sink, values[2]);
    sink.put(']');
}

void write_json(TextSink& sink, const NeighborList& list, const PairTableHeader& header,
                Progress& progress) {
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
    const std::size_t n = list.size();
    json_array(sink, "i", n, [&](std::size_t k) {
        sink.put_integer(list.i()[k]);
        progress.update(k);
    });
    json_array(sink, "j", n, [&](std::size_t k) {
        sink.put_integer(list.j()[k]);
        progress.update(n + k);
    });
    json_array(sink, "S", n, [&](std::size_t k) {
        json_triple(sink, list.shifts().data() + 3 * k);
        progress.update(2 * n + k);
    });
    json_array(sink, "d", n, [&](std::size_t k) {
        sink.put_real(list.distances()[k]);
        progress.update(3 * n + k);
    });
    json_array(sink, "D", n, [&](std::size_t k) {
        json_triple(sink, list.vectors().data() + 3 * k);
        progress.update(4 * n + k);
    });
    sink.put("\n}\n");
}

void write_nearest_rows(TextSink& sink, const NearestNeighbors& nearest, char separator,
                        Progress& progress) {
    for (std::size_t e = 0; e < nearest.j.size(); ++e) {
        sink.put_integer(e / nearest.k);
        sink.put(separator);
        sink.put_integer(nearest.j[e]);
        for (std::size_t c = 0; c < 3; ++c) {
            sink.put(separator);
            sink.put_integer(nearest.shifts[3 * e + c]);
        }
        sink.put(separator);
        sink.put_real(nearest.distances[e]);
        sink.put('\n');
        progress.update(e);
    }
}

} // namespace

void write_nearest(TextSink& sink, const NearestNeighbors& nearest, TableFormat format,
                   const std::string& file, bool show_progress) {
    const std::size_t n = nearest.j.size();
    Progress progress("writing neighbours", format == TableFormat::json ? 4 * n : n, show_progress);
    switch (format) {
    case TableFormat::tsv:
        sink.put("# i j Sa Sb Sc d\n");
        write_nearest_rows(sink, nearest, '\t', progress);
        break;
    case TableFormat::csv:
        sink.put("i,j,Sa,Sb,Sc,d\n");
        write_nearest_rows(sink, nearest, ',', progress);
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
        json_array(sink, "i", n, [&](std::size_t e) {
            sink.put_integer(e / nearest.k);
            progress.update(e);
        });
        json_array(sink, "j", n, [&](std::size_t e) {
            sink.put_integer(nearest.j[e]);
            progress.update(n + e);
        });
        json_array(sink, "S", n, [&](std::size_t e) {
            json_triple(sink, nearest.shifts.data() + 3 * e);
            progress.update(2 * n + e);
        });
        json_array(sink, "d", n, [&](std::size_t e) {
            sink.put_real(nearest.distances[e]);
            progress.update(3 * n + e);
        });
        sink.put("\n}\n");
        break;
    }
}

void write_pairs(TextSink& sink, const NeighborList& list, TableFormat format,
                 const PairTableHeader& header, bool show_progress) {
    const std::size_t passes = format == TableFormat::json ? 5 : 1;
    Progress progress("writing pairs", passes * list.size(), show_progress);
    switch (format) {
    case TableFormat::tsv:
        sink.put("# i j Sa Sb Sc d Dx Dy Dz\n");
        write_rows(sink, list, '\t', progress);
        break;
    case TableFormat::csv:
        sink.put("i,j,Sa,Sb,Sc,d,Dx,Dy,Dz\n");
        write_rows(sink, list, ',', progress);
        break;
    case TableFormat::json:
        write_json(sink, list, header, progress);
        break;
    }
}

} // namespace tricell::cli
