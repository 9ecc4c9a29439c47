// Space groups and reduced cells through spglib.
//
// find_space_group() hands the box and the fractional positions to spglib. Atoms are told apart
// by element and occupancy, so a half-occupied site is not equivalent to a fully occupied one of
// the same element; a disordered structure listing every partial site (both orientations of a
// disordered OH, say) keeps the symmetry of the average structure. niggli_reduce() returns the
// Niggli-reduced basis of the same lattice (spglib's algorithm, Krivy & Gruber 1976 with
// Grosse-Kunstleve's tolerances). Both need a box periodic along all three axes.
#pragma once

#include <string>

#include "tricell/box.hpp"
#include "tricell/io/export.hpp"
#include "tricell/io/structure.hpp"

namespace tricell::io {

struct SpaceGroupInfo {
    /// International Tables number, 1 to 230.
    int number = 0;
    /// Short Hermann-Mauguin symbol as spglib writes it ("P3_221", "Fd-3m").
    std::string international;
    /// Hall symbol of the setting spglib found ("P 32 2\"").
    std::string hall;
};

/// The space group of the structure with tolerance `symprec` (Angstrom). Throws
/// InvalidArgument for symprec <= 0 or a box not periodic along all axes, and GeometryError
/// when spglib finds no space group (the message carries spglib's reason).
TRICELL_IO_API SpaceGroupInfo find_space_group(const Structure& structure, double symprec = 1e-5);

/// The Niggli-reduced cell of the lattice of `box` (same periodicity). Throws InvalidArgument
/// for tolerance <= 0 or a box not periodic along all axes, GeometryError if spglib fails.
TRICELL_IO_API Box niggli_reduce(const Box& box, double tolerance = 1e-5);

/// Version of the spglib library linked in ("2.0.2").
TRICELL_IO_API std::string spglib_version();

} // namespace tricell::io
