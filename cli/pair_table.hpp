// The neighbour list as text (tricell neighbors, docs/contract.md): TSV with a '# i j Sa Sb Sc d Dx
// Dy Dz' header line, CSV with an 'i,j,Sa,Sb,Sc,d,Dx,Dy,Dz' header, or one JSON object with an
// array per column; the k nearest neighbours of every atom likewise, with the columns
// i j Sa Sb Sc d. Reals are the shortest text that reads back exactly (text.hpp).
#pragma once

#include <cstddef>
#include <string>

#include <tricell/analysis/nearest.hpp>
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

/// Writes `list` (with shifts, distances and vectors) in `format`, formatting on `threads`
/// threads (the text is the same for any number); with `progress`, shows how far it got on a
/// terminal (progress.hpp).
void write_pairs(TextSink& sink, const NeighborList& list, TableFormat format,
                 const PairTableHeader& header, int threads, bool progress);

/// Writes the k nearest neighbours of every atom in `format` (atom i's rows in order, nearest
/// first); JSON has "k" instead of "cutoff" and "half".
void write_nearest(TextSink& sink, const NearestNeighbors& nearest, TableFormat format,
                   const std::string& file, int threads, bool progress);

} // namespace tricell::cli
