#include "pair_table.hpp"

#include <cstdio>

#include "progress.hpp"
#include "text.hpp"

namespace tricell::cli {

std::string json_string(const std::string& text) {
    std::string out = "\"";
    for (char c : text) {
        if (c == '"' || c == '\\') {
            out += '\\';
            out += c;
        } else if (static_cast<unsigned char>(c) < 0x20) {
            char escaped[8];
            std::snprintf(escaped, sizeof escaped, "\\u%04x", c);
            out += escaped;
        } else {
            out += c;
        }
    }
    return out + "\"";
}

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
    const auto triple = [&](auto* values, std::size_t k, auto put) {
        sink.put('[');
        put(values[3 * k]);
        sink.put(", ");
        put(values[3 * k + 1]);
        sink.put(", ");
        put(values[3 * k + 2]);
        sink.put(']');
    };
    const auto integer = [&](auto x) { sink.put_integer(x); };
    const auto real = [&](double x) { sink.put_real(x); };
    json_array(sink, "i", n, [&](std::size_t k) {
        sink.put_integer(list.i()[k]);
        progress.update(k);
    });
    json_array(sink, "j", n, [&](std::size_t k) {
        sink.put_integer(list.j()[k]);
        progress.update(n + k);
    });
    json_array(sink, "S", n, [&](std::size_t k) {
        triple(list.shifts().data(), k, integer);
        progress.update(2 * n + k);
    });
    json_array(sink, "d", n, [&](std::size_t k) {
        sink.put_real(list.distances()[k]);
        progress.update(3 * n + k);
    });
    json_array(sink, "D", n, [&](std::size_t k) {
        triple(list.vectors().data(), k, real);
        progress.update(4 * n + k);
    });
    sink.put("\n}\n");
}

} // namespace

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
