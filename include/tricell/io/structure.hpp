// Crystal structures read from files: CIF, VASP POSCAR/CONTCAR and (extended) XYZ.
//
// Every reader returns a Structure: a Box, and per atom its element symbol, Cartesian position,
// occupancy and label. The format is chosen from the file name (docs/contract.md, command line)
// unless ReadOptions::format says otherwise. How each format is read:
//
// - CIF: the first data block with _atom_site_fract_x. Cell from _cell_length_* and
//   _cell_angle_* (a along x, b in the xy plane). Symmetry operators from the
//   _symmetry_equiv_pos_as_xyz or _space_group_symop_operation_xyz loop when present, else from
//   the Hall or H-M symbol, else P 1. The asymmetric unit is expanded to the full unit cell in a
//   fixed order: for each atom-site row in file order, its images in operator order, each
//   wrapped into [0, 1). An image closer than ReadOptions::merge_distance (minimum-image,
//   Cartesian) to an image already kept for the same row is dropped, so an atom on a special
//   position appears once. Occupancies are kept as given (default 1).
// - POSCAR/CONTCAR (VASP 5): scale factor (negative: target volume; or three per-axis factors),
//   lattice vectors as rows, element names, counts, optional Selective dynamics, Direct or
//   Cartesian coordinates (Cartesian ones scaled like the lattice). Positions in file order,
//   not wrapped. Fully periodic.
// - Extended XYZ as ASE writes it: Lattice="ax ay az bx by bz cx cy cz" (rows), pbc="T T F"
//   (default T T T with a Lattice), Properties=species:S:1:pos:R:3:... (the default when
//   absent). Without Lattice the system is open: all axes non-periodic, and the box is the
//   orthogonal frame with edges (extent of the positions along x, y, z) + 1 Angstrom. Only the
//   first frame is read (io::FrameReader, trajectory.hpp, reads every frame). Positions not
//   wrapped.
//
// Species are element symbols in canonical case ("Si"); POSCAR POTCAR suffixes ("Fe_pv") and
// CIF charges ("Fe2+") are dropped. Every error is a tricell::ParseError whose what() reads
// "FILE:LINE: what is wrong, what was expected" (line 0, i.e. "FILE: ...", when no line applies).
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "tricell/box.hpp"
#include "tricell/io/export.hpp"

namespace tricell::io {

enum class Format { cif, xyz, poscar };

/// Atoms in a box. All per-atom vectors have the same length.
struct Structure {
    Box box = Box::from_columns(Eigen::Matrix3d::Identity());
    /// Element symbol per atom ("Si", "O").
    std::vector<std::string> species;
    /// Cartesian positions, in the length unit of the file (Angstrom).
    std::vector<Eigen::Vector3d> positions;
    /// Site occupancy per atom, 1 unless the file says otherwise (CIF).
    std::vector<double> occupancies;
    /// CIF: the _atom_site_label of the row the atom came from (shared by its images);
    /// POSCAR and XYZ: the species as written in the file.
    std::vector<std::string> labels;
    /// Where the structure was read from (the file name given to the reader).
    std::string source;

    std::size_t size() const { return positions.size(); }
};

struct TRICELL_IO_API ReadOptions {
    /// File format; empty means guess it from the file name (format_from_name).
    std::optional<Format> format;
    /// CIF expansion: symmetry images of one atom-site row closer than this (Angstrom,
    /// minimum-image) are one atom. The default 0.01 Angstrom absorbs coordinates rounded to
    /// four decimals (such as 0.3333 for 1/3) in cells up to ~50 Angstrom, and is far below
    /// any distance between distinct atoms. Must be finite and >= 0. A CIF with more than one
    /// symmetry operator whose cell is narrower than twice this is refused (ParseError).
    double merge_distance = 0.01;
    /// Refuse (ParseError, before reading the atoms) a file with more atoms than this: a POSCAR
    /// or XYZ count, or a CIF's sites times its symmetry operators. The default, 10^7 atoms,
    /// is about 1 GB of Structure. 0 means no limit.
    std::size_t max_atoms = 10'000'000;

    /// Throws InvalidArgument naming the offending field and value.
    void validate() const;
};

/// Reads the file at `path`. Throws ParseError (also when the file cannot be opened).
TRICELL_IO_API Structure read_structure(const std::string& path, const ReadOptions& options = {});

/// Parses `text` as the contents of a file called `name` (used for the format guess and in
/// error messages).
TRICELL_IO_API Structure parse_structure(const std::string& text, const std::string& name,
                                         const ReadOptions& options = {});

/// Format from a file name: *.cif; *.xyz, *.extxyz; POSCAR*, CONTCAR*, *.vasp, *.poscar
/// (case-insensitive). Throws ParseError(path, 0, ...) for anything else.
TRICELL_IO_API Format format_from_name(const std::string& path);

/// Format from its name as a user types it: "cif", "xyz" or "extxyz", "poscar" or "vasp"
/// (case-insensitive). Throws InvalidArgument otherwise.
TRICELL_IO_API Format parse_format(const std::string& name);

/// "cif", "xyz" or "poscar".
TRICELL_IO_API const char* format_name(Format format);

/// Canonical element symbol for a token: an element symbol in any case ("si", "SI" give "Si")
/// or, when allow_number is set, an atomic number ("14"). Empty when it is neither.
TRICELL_IO_API std::string element_symbol(const std::string& token, bool allow_number = false);

/// Chemical formula of the whole structure in Hill order (C, then H, then the others
/// alphabetically; alphabetical throughout without C), counts weighted by occupancy and
/// printed with up to 6 significant digits, 1 omitted: "O6 Si3", "Fe3.768 O4".
TRICELL_IO_API std::string formula(const Structure& structure);

/// Sum of the occupancies (the occupancy-weighted atom count).
TRICELL_IO_API double occupied_count(const Structure& structure);

} // namespace tricell::io
