// The arguments of the module's functions, checked and converted to tricell's C++ types; every
// binding reads its arguments through these (the output arrays are columns.hpp's job).
//
// Arrays: every array argument goes through numpy_array() (np.asarray, so lists, tuples and
// objects with __array__ work), and its dtype.kind is classified before anything is cast, so
// a cast never hides a wrong kind of value. This file holds the whole rule:
//   - positions, boxes and per-atom values (points, box, radii) take real numbers: kinds 'f'
//     (float16 to longdouble), 'i' and 'u', any byte order, memory order, strides or
//     writeability; they are converted once to C-contiguous float64 (a native float64
//     C-contiguous input is used as it is), so every accepted layout gives the same result;
//     points are N x 3 (an empty list or shape (0, 3) is no atoms), a box 3 x 3;
//   - species take integers ('i', 'u'), or floats whose values are whole numbers;
//   - pair indices and shifts (the i, j, S of a list to verify) take integers ('i', 'u') only,
//     any width, converted to int64 (a uint64 above 2^63 - 1 is a ValueError); an index out of
//     range is a property of the list, reported by the verification, not refused here;
//   - periodic takes bools, or the integers 0 and 1; one value (every axis) or three;
//   - any other kind is a TypeError: bool ('b') for numbers, complex ('c', never cast to its
//     real part), datetime and timedelta ('M', 'm'), object ('O', also a list mixing numbers
//     and None), bytes and str ('S', 'U', never parsed as numbers) and structured ('V');
//   - a wrong shape (rank, width, count, a 0-d scalar), a ragged nested list, a fractional or
//     out-of-range species, or a periodic flag other than 0 or 1 is a ValueError; an object
//     numpy cannot convert at all (its __array__ raising) is a TypeError.
// Every message names the argument and what it got ("points must hold real numbers (float or
// int), not complex (got dtype complex128, shape (4, 3))"). Values are otherwise left to the
// library to check (a NaN position is reported by tricell with its index), so no rule is
// written twice. tricell._tricell._as_array applies the same rules for the Python drop-ins.
//
// The other arguments: cutoff (a number, a dict of species pairs or None) and max_bytes (None
// or a whole number >= 0), each a ValueError naming it and what it got otherwise.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <tricell/box.hpp>
#include <tricell/neighbor_list.hpp>

namespace tricell::python {

namespace py = pybind11;

using DoubleArray = py::array_t<double, py::array::c_style | py::array::forcecast>;

/// `value` as a numpy array (np.asarray), nothing cast yet; a ragged nested sequence is a
/// ValueError, anything numpy cannot convert a TypeError, both naming `name`.
py::array numpy_array(const py::handle& value, const char* name);

/// Real numbers of any shape as C-contiguous float64; TypeError for any other kind.
DoubleArray real_array(const py::handle& value, const char* name);

/// N x 3 positions (an empty list or an empty (0, 3) array is no atoms).
DoubleArray points_array(const py::handle& points, const char* name = "points");

/// A 3 x 3 box, the lattice vectors as rows.
DoubleArray box_array(const py::handle& box, const char* name = "box");

/// N real values (one per atom), checked against the atom count.
DoubleArray per_atom_array(const py::handle& values, std::size_t atoms, const char* name);

/// A 1-D array of integer species of any length.
std::vector<std::int32_t> species_array(const py::handle& values, const char* name);

/// N integer species (one per atom).
std::vector<std::int32_t> per_atom_species(const py::handle& values, std::size_t atoms,
                                           const char* name = "species");

/// `rows` integers (width 1: shape (rows,)), or rows x 3 ones (width 3) when rows is -1 any
/// count, as C-contiguous int64; `rows_name` names the array whose length this must match.
std::vector<std::int64_t> index_array(const py::handle& values, const char* name, py::ssize_t rows,
                                      int width, const char* rows_name);

/// Real numbers of shape (rows,) (width 1) or (rows, 3) (width 3), as C-contiguous float64.
DoubleArray pair_value_array(const py::handle& values, const char* name, py::ssize_t rows,
                             int width, const char* rows_name);

/// Periodicity from one bool (every axis) or three.
Periodicity periodicity(const py::handle& periodic, const char* name = "periodic");

/// The periodicity of each of `count` structures of a batch: one bool or three for all of them,
/// or one row of three per structure (shape (count, 3)).
std::vector<Periodicity> periodicities(const py::handle& periodic, std::size_t count,
                                       const char* name = "periodic");

/// The pointer array of a concatenated batch: B + 1 integers starting at 0, never decreasing,
/// ending at `points` (structure s owns rows ptr[s]:ptr[s + 1] of the points).
std::vector<std::int64_t> batch_pointer(const py::handle& values, std::size_t points,
                                        const char* name = "batch_ptr");

/// `count` boxes of a batch, shape (count, 3, 3), the lattice vectors of each as rows.
DoubleArray boxes_array(const py::handle& boxes, std::size_t count, const char* name = "boxes");

/// A Box from lattice vectors as the rows of a 3 x 3 array-like, and `periodic` given as one
/// bool or three.
Box box_from_rows(const py::handle& box, const py::handle& periodic, const char* box_name = "box",
                  const char* periodic_name = "periodic");

/// The checks above for Python code (tricell._tricell._as_array): `rule` is "points", "box",
/// "real", "species" or "periodic"; returns the converted array (float64, int32 or 3 bools).
py::array checked_array(const py::handle& value, const std::string& name, const std::string& rule);

/// repr(value), at most 80 characters, or its type's name when repr itself fails: what an
/// argument got, for messages.
std::string described(const py::handle& value);

/// The cutoff argument of NeighborList and verify into `options`: a float (one cutoff), a dict
/// {(species a, species b): cutoff} (a per-species-pair table) or None (per-atom radii, given
/// elsewhere). ValueError for anything else.
void set_cutoff(const py::object& cutoff, NeighborOptions& options);

/// The max_bytes argument: None is the library's default (NeighborOptions().max_bytes), else a
/// whole number >= 0 (0: no limit). ValueError naming max_bytes for anything else.
std::size_t max_bytes_argument(const py::object& value);

} // namespace tricell::python
