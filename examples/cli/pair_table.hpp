// The neighbour list as text (tricell neighbors, CONTRACT §3): TSV with a '# i j Sa Sb Sc d Dx
// Dy Dz' header line, CSV with an 'i,j,Sa,Sb,Sc,d,Dx,Dy,Dz' header, or one JSON object with an
// array per column. Reals are the shortest text that reads back exactly (text.hpp).
#pragma once

#include <cstddef>
#include <string>

#include <tricell/neighbor_list.hpp>

#include "cli.hpp"

namespace tricell::cli {

class TextSink;

/// What the JSON object says besides the columns.
struct PairTableHeader {
    std::string file;
    std::size_t atoms = 0;
    double cutoff = 0;
    bool half = false;
};

/// Writes `list` (with shifts, distances and vectors) in `format`; with `progress`, shows how
/// far it got on a terminal (progress.hpp).
void write_pairs(TextSink& sink, const NeighborList& list, TableFormat format,
                 const PairTableHeader& header, bool progress);

/// A JSON string literal of `text` (quotes, backslashes and control characters escaped).
std::string json_string(const std::string& text);

} // namespace tricell::cli
