// Translations between numpy arrays and tricell's C++ types, shared by the module's bindings.
//
// Inputs: any array-like (lists, float32, non-contiguous or strided arrays) is converted once to
// a C-contiguous float64 array, whose shape is checked here with a message naming the argument
// and the shape received. Values are left to the library to check (a NaN position is reported
// by tricell with its index), so no rule is written twice.
//
// Outputs: the columns of a tricell::NeighborList either copied into fresh numpy arrays or
// handed out as views whose base object keeps the list's buffers alive (PairColumns). Letters
// of a quantities string name the columns: i, j, S (N x 3 shifts), d, D (N x 3 vectors) and
// P (N x 2 pairs (i, j), always a fresh array since i and j are stored apart).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <tricell/batch.hpp>
#include <tricell/box.hpp>
#include <tricell/neighbor_list.hpp>

namespace tricell::python {

namespace py = pybind11;

using DoubleArray = py::array_t<double, py::array::c_style | py::array::forcecast>;

/// N x 3 positions from any array-like; `name` is used in error messages.
DoubleArray points_array(const py::handle& points, const char* name = "points");

/// N values (one per atom) from any array-like, checked against the atom count.
DoubleArray per_atom_array(const py::handle& values, std::size_t atoms, const char* name);

/// N integer species (one per atom) from any array-like of integers.
std::vector<std::int32_t> per_atom_species(const py::handle& values, std::size_t atoms);

/// A Box from lattice vectors as the rows of a 3 x 3 array-like, and `periodic` given as one
/// bool or three.
Box box_from_rows(const py::handle& box, const py::handle& periodic);

/// Which NeighborList columns a quantities string needs; throws ValueError for other letters.
Quantities parse_quantities(const std::string& letters);

/// The columns of a computed list as numpy arrays in the order of `letters`: one array for a
/// single letter, a tuple otherwise. With `owner` non-null the arrays (except P) are views whose
/// base holds `owner`; otherwise they are copies.
py::object pair_columns(const NeighborList& list, const std::string& letters,
                        const std::shared_ptr<const NeighborList>& owner);

/// The lists of a batch, always copied: a tuple of the per-structure pair offsets (int64,
/// structures + 1) followed by the columns of `letters` over all structures.
py::tuple batch_columns(const BatchList& list, const std::string& letters);

} // namespace tricell::python
