#include "arrays.hpp"

#include <cstdint>
#include <cstring>
#include <sstream>
#include <vector>

namespace tricell::python {

namespace {

std::string shape_of(const py::array& a) {
    std::ostringstream out;
    out << '(';
    for (py::ssize_t k = 0; k < a.ndim(); ++k) {
        out << (k ? ", " : "") << a.shape(k);
    }
    out << (a.ndim() == 1 ? ",)" : ")");
    return out.str();
}

[[noreturn]] void value_error(const std::string& message) {
    throw py::value_error(message);
}

// A view (base non-null) or a copy of `count` rows of `width` elements starting at `data`.
template <class T>
py::array column(const T* data, std::size_t count, std::size_t width, const py::object& base) {
    std::vector<py::ssize_t> shape{static_cast<py::ssize_t>(count)};
    if (width > 1) {
        shape.push_back(static_cast<py::ssize_t>(width));
    }
    if (base && count > 0) {
        return py::array_t<T>(shape, data, base);
    }
    py::array_t<T> out(shape);
    if (count > 0) {
        std::memcpy(out.mutable_data(), data, count * width * sizeof(T));
    }
    return std::move(out);
}

} // namespace

DoubleArray points_array(const py::handle& points, const char* name) {
    auto a = DoubleArray::ensure(points);
    if (!a) {
        throw py::error_already_set();
    }
    // An empty list or array means no atoms, whatever its shape.
    if (a.size() == 0) {
        return DoubleArray(std::vector<py::ssize_t>{0, 3});
    }
    if (a.ndim() != 2 || a.shape(1) != 3) {
        value_error(std::string(name) + " must be an array of shape (N, 3) (got shape " +
                    shape_of(a) + ")");
    }
    return a;
}

DoubleArray per_atom_array(const py::handle& values, std::size_t atoms, const char* name) {
    auto a = DoubleArray::ensure(values);
    if (!a) {
        throw py::error_already_set();
    }
    if (a.ndim() != 1 || static_cast<std::size_t>(a.shape(0)) != atoms) {
        value_error(std::string(name) + " must have one value per atom, shape (" +
                    std::to_string(atoms) + ",) (got shape " + shape_of(a) + ")");
    }
    return a;
}

std::vector<std::int32_t> per_atom_species(const py::handle& values, std::size_t atoms) {
    const py::array a = py::array::ensure(values);
    if (!a || (a.size() > 0 && a.dtype().kind() != 'i' && a.dtype().kind() != 'u')) {
        PyErr_Clear();
        value_error("species must be integers, one per atom (got " +
                    py::repr(values).cast<std::string>().substr(0, 80) + ")");
    }
    if (a.ndim() != 1 || static_cast<std::size_t>(a.shape(0)) != atoms) {
        value_error("species must have one value per atom, shape (" + std::to_string(atoms) +
                    ",) (got shape " + shape_of(a) + ")");
    }
    const auto wide = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>(a);
    std::vector<std::int32_t> out(atoms);
    for (std::size_t k = 0; k < atoms; ++k) {
        const std::int64_t v = wide.data()[k];
        if (v < INT32_MIN || v > INT32_MAX) {
            value_error("species[" + std::to_string(k) + "] does not fit a 32-bit integer (got " +
                        std::to_string(v) + ")");
        }
        out[k] = static_cast<std::int32_t>(v);
    }
    return out;
}

Box box_from_rows(const py::handle& box, const py::handle& periodic) {
    auto a = DoubleArray::ensure(box);
    if (!a) {
        throw py::error_already_set();
    }
    if (a.ndim() != 2 || a.shape(0) != 3 || a.shape(1) != 3) {
        value_error("box must be a 3 x 3 array with the lattice vectors as rows (got shape " +
                    shape_of(a) + ")");
    }
    Eigen::Matrix3d rows;
    for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) {
            rows(r, c) = a.at(r, c);
        }
    }
    Periodicity pbc;
    if (py::isinstance<py::bool_>(periodic) || py::isinstance<py::int_>(periodic)) {
        pbc.axes.fill(periodic.cast<bool>());
    } else {
        auto flags = py::array_t<bool, py::array::forcecast>::ensure(periodic);
        if (!flags || flags.ndim() != 1 || flags.shape(0) != 3) {
            PyErr_Clear();
            value_error("periodic must be a bool or three bools (got " +
                        py::repr(periodic).cast<std::string>() + ")");
        }
        for (int k = 0; k < 3; ++k) {
            pbc.axes[static_cast<std::size_t>(k)] = flags.at(k);
        }
    }
    return Box::from_rows(rows, pbc);
}

Quantities parse_quantities(const std::string& letters) {
    Quantities q;
    q.shifts = q.distances = q.vectors = false;
    for (char letter : letters) {
        switch (letter) {
        case 'i':
        case 'j':
        case 'P':
        case 'o':
            break;
        case 'S':
            q.shifts = true;
            break;
        case 'd':
            q.distances = true;
            break;
        case 'D':
            q.vectors = true;
            break;
        default:
            value_error("unknown quantity '" + std::string(1, letter) + "' in '" + letters +
                        "' (expected letters among i, j, S, d, D, P, o)");
        }
    }
    if (letters.empty()) {
        value_error("quantities must name at least one of i, j, S, d, D, P (got '')");
    }
    return q;
}

namespace {
// The columns of a list or of a batch's lists (the same accessors), views on `base` when it is
// set, copies otherwise.
template <class List>
py::object columns_of(const List& list, const std::string& letters, const py::object& base) {
    const std::size_t n = list.size();
    py::tuple out(letters.size());
    for (std::size_t k = 0; k < letters.size(); ++k) {
        py::array a;
        switch (letters[k]) {
        case 'i':
            a = column(list.i().data(), n, 1, base);
            break;
        case 'j':
            a = column(list.j().data(), n, 1, base);
            break;
        case 'S':
            a = column(list.shifts().data(), n, 3, base);
            break;
        case 'd':
            a = column(list.distances().data(), n, 1, base);
            break;
        case 'D':
            a = column(list.vectors().data(), n, 3, base);
            break;
        case 'P': {
            py::array_t<std::uint32_t> pairs(
                std::vector<py::ssize_t>{static_cast<py::ssize_t>(n), 2});
            auto* p = pairs.mutable_data();
            for (std::size_t m = 0; m < n; ++m) {
                p[2 * m] = list.i()[m];
                p[2 * m + 1] = list.j()[m];
            }
            a = pairs;
            break;
        }
        case 'o': {
            const std::vector<std::size_t>& offsets = list.offsets();
            py::array_t<std::int64_t> copy(static_cast<py::ssize_t>(offsets.size()));
            std::copy(offsets.begin(), offsets.end(), copy.mutable_data());
            a = copy;
            break;
        }
        }
        out[k] = a;
    }
    if (letters.size() == 1) {
        return out[0];
    }
    return std::move(out);
}

} // namespace

py::object pair_columns(const NeighborList& list, const std::string& letters,
                        const std::shared_ptr<const NeighborList>& owner) {
    py::object base;
    if (owner) {
        auto* keep = new std::shared_ptr<const NeighborList>(owner);
        base = py::capsule(
            keep, [](void* p) { delete static_cast<std::shared_ptr<const NeighborList>*>(p); });
    }
    return columns_of(list, letters, base);
}

py::tuple batch_columns(const BatchList& list, const std::string& letters) {
    const std::vector<std::size_t>& offsets = list.pair_offsets();
    py::array_t<std::int64_t> pair_offsets(static_cast<py::ssize_t>(offsets.size()));
    for (std::size_t s = 0; s < offsets.size(); ++s) {
        pair_offsets.mutable_data()[s] = static_cast<std::int64_t>(offsets[s]);
    }
    py::object columns = columns_of(list, letters, py::object());
    py::tuple out(1 + letters.size());
    out[0] = pair_offsets;
    if (letters.size() == 1) {
        out[1] = columns;
    } else {
        const py::tuple t = columns.cast<py::tuple>();
        for (std::size_t k = 0; k < letters.size(); ++k) {
            out[k + 1] = t[k];
        }
    }
    return out;
}

} // namespace tricell::python
