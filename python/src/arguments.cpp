// The arguments of the module's functions checked and converted (the rules are in
// arguments.hpp): arrays by the kind of their values, then their shape; the cutoff and max_bytes
// by their Python type.
#include "arguments.hpp"

#include "batch_layout.hpp"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <sstream>
#include <utility>
#include <vector>

namespace tricell::python {

namespace {

std::string shape_of(const py::array& a) {
    std::ostringstream out;
    out.exceptions(std::ios::badbit); // out of memory: bad_alloc, not a shortened text
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

std::string dtype_of(const py::array& a) {
    return py::str(a.dtype()).cast<std::string>();
}

// "dtype complex128, shape (4, 3)": what an argument got, for messages.
std::string got(const py::array& a) {
    return "dtype " + dtype_of(a) + ", shape " + shape_of(a);
}

// What a dtype kind refused for numbers holds, for messages.
const char* kind_name(char kind) {
    switch (kind) {
    case 'b':
        return "bool";
    case 'c':
        return "complex";
    case 'M':
        return "datetime";
    case 'm':
        return "timedelta";
    case 'O':
        return "Python objects";
    case 'S':
        return "bytes";
    case 'U':
        return "str";
    case 'V':
        return "structured or void";
    default:
        return "not numbers";
    }
}

bool is_real_kind(char kind) {
    return kind == 'f' || kind == 'i' || kind == 'u';
}

// The first line of a Python error's message, at most 120 characters.
std::string short_message(const py::error_already_set& e) {
    std::string text = py::str(e.value()).cast<std::string>();
    text = text.substr(0, text.find('\n'));
    return text.size() > 120 ? text.substr(0, 117) + "..." : text;
}

} // namespace

py::array numpy_array(const py::handle& value, const char* name) {
    if (py::isinstance<py::array>(value)) {
        return py::reinterpret_borrow<py::array>(value);
    }
    try {
        return py::module_::import("numpy").attr("asarray")(value).cast<py::array>();
    } catch (py::error_already_set& e) {
        // An interrupt or a failed allocation is no property of the argument: it goes on.
        if (!e.matches(PyExc_Exception) || e.matches(PyExc_MemoryError)) {
            throw;
        }
        if (e.matches(PyExc_ValueError)) {
            throw py::value_error(std::string(name) +
                                  " must be a rectangular array of numbers (got a ragged or "
                                  "unconvertible sequence: " +
                                  short_message(e) + ")");
        }
        throw py::type_error(std::string(name) + " cannot be converted to a numpy array (got " +
                             std::string(Py_TYPE(value.ptr())->tp_name) + ": " + short_message(e) +
                             ")");
    }
}

DoubleArray real_array(const py::handle& value, const char* name) {
    const py::array a = numpy_array(value, name);
    const char kind = a.dtype().kind();
    if (!is_real_kind(kind)) {
        throw py::type_error(std::string(name) + " must hold real numbers (float or int), not " +
                             kind_name(kind) + " (got " + got(a) + ")");
    }
    return DoubleArray(a); // a copy unless a is C-contiguous native float64 already
}

DoubleArray points_array(const py::handle& points, const char* name) {
    DoubleArray a = real_array(points, name);
    // An empty list, or an empty array of N x 3 points, means no atoms.
    if (a.size() == 0 && (a.ndim() == 1 || (a.ndim() == 2 && a.shape(1) == 3))) {
        return DoubleArray(std::vector<py::ssize_t>{0, 3});
    }
    if (a.ndim() != 2 || a.shape(1) != 3) {
        value_error(std::string(name) + " must be an array of shape (N, 3) (got shape " +
                    shape_of(a) + ")");
    }
    return a;
}

DoubleArray box_array(const py::handle& box, const char* name) {
    DoubleArray a = real_array(box, name);
    if (a.ndim() != 2 || a.shape(0) != 3 || a.shape(1) != 3) {
        value_error(std::string(name) +
                    " must be a 3 x 3 array with the lattice vectors as rows (got shape " +
                    shape_of(a) + ")");
    }
    return a;
}

DoubleArray per_atom_array(const py::handle& values, std::size_t atoms, const char* name) {
    DoubleArray a = real_array(values, name);
    if (a.ndim() != 1 || static_cast<std::size_t>(a.shape(0)) != atoms) {
        value_error(std::string(name) + " must have one value per atom, shape (" +
                    std::to_string(atoms) + ",) (got shape " + shape_of(a) + ")");
    }
    return a;
}

std::vector<std::int32_t> species_array(const py::handle& values, const char* name) {
    const py::array a = numpy_array(values, name);
    const char kind = a.dtype().kind();
    if (!is_real_kind(kind)) {
        throw py::type_error(std::string(name) + " must be integers, not " + kind_name(kind) +
                             " (got " + got(a) + ")");
    }
    if (a.ndim() != 1) {
        value_error(std::string(name) + " must be a 1-D array of integers (got shape " +
                    shape_of(a) + ")");
    }
    const auto n = static_cast<std::size_t>(a.shape(0));
    std::vector<std::int32_t> out(n);
    const auto out_of_range = [&](std::size_t k, const std::string& v) {
        value_error(std::string(name) + "[" + std::to_string(k) +
                    "] does not fit a 32-bit integer (got " + v + ", dtype " + dtype_of(a) + ")");
    };
    if (kind == 'u') {
        const py::array_t<std::uint64_t, py::array::c_style | py::array::forcecast> wide(a);
        for (std::size_t k = 0; k < n; ++k) {
            const std::uint64_t v = wide.data()[k];
            if (v > static_cast<std::uint64_t>(INT32_MAX)) {
                out_of_range(k, std::to_string(v));
            }
            out[k] = static_cast<std::int32_t>(v);
        }
    } else if (kind == 'i') {
        const py::array_t<std::int64_t, py::array::c_style | py::array::forcecast> wide(a);
        for (std::size_t k = 0; k < n; ++k) {
            const std::int64_t v = wide.data()[k];
            if (v < INT32_MIN || v > INT32_MAX) {
                out_of_range(k, std::to_string(v));
            }
            out[k] = static_cast<std::int32_t>(v);
        }
    } else {
        const DoubleArray wide(a);
        for (std::size_t k = 0; k < n; ++k) {
            const double v = wide.data()[k];
            if (!(std::floor(v) == v)) { // NaN and infinities too
                std::ostringstream text;
                text.exceptions(std::ios::badbit);
                text << name << " must be integers (got " << name << "[" << k << "] = " << v
                     << ", dtype " << dtype_of(a) << ")";
                value_error(text.str());
            }
            if (v < INT32_MIN || v > INT32_MAX) {
                std::ostringstream text;
                text.exceptions(std::ios::badbit);
                text << v;
                out_of_range(k, text.str());
            }
            out[k] = static_cast<std::int32_t>(v);
        }
    }
    return out;
}

std::vector<std::int32_t> per_atom_species(const py::handle& values, std::size_t atoms,
                                           const char* name) {
    std::vector<std::int32_t> out = species_array(values, name);
    if (out.size() != atoms) {
        value_error(std::string(name) + " must have one value per atom, shape (" +
                    std::to_string(atoms) + ",) (got shape (" + std::to_string(out.size()) + ",))");
    }
    return out;
}

namespace {

// "(rows,)" or "(rows, 3)" (rows < 0: "N"), for messages.
std::string wanted_shape(py::ssize_t rows, int width) {
    const std::string count = rows < 0 ? "N" : std::to_string(rows);
    return width == 1 ? "(" + count + ",)" : "(" + count + ", 3)";
}

// Whether `a` has shape (rows,) or (rows, 3), rows < 0 meaning any; an empty array of rank 1
// also passes as width 3 (an empty list).
bool has_rows(const py::array& a, py::ssize_t rows, int width) {
    if (width == 3 && a.ndim() == 1 && a.shape(0) == 0 && rows <= 0) {
        return true;
    }
    const bool shape = width == 1 ? a.ndim() == 1 : (a.ndim() == 2 && a.shape(1) == 3);
    return shape && (rows < 0 || a.shape(0) == rows);
}

void require_rows(const py::array& a, const char* name, py::ssize_t rows, int width,
                  const char* rows_name) {
    if (!has_rows(a, rows, width)) {
        std::string text = std::string(name) + " must have shape " + wanted_shape(rows, width);
        if (rows >= 0 && rows_name != nullptr) {
            text += std::string(", one entry per entry of ") + rows_name;
        }
        value_error(text + " (got shape " + shape_of(a) + ")");
    }
}

} // namespace

std::vector<std::int64_t> index_array(const py::handle& values, const char* name, py::ssize_t rows,
                                      int width, const char* rows_name) {
    const py::array a = numpy_array(values, name);
    const char kind = a.dtype().kind();
    if (kind != 'i' && kind != 'u') {
        throw py::type_error(std::string(name) + " must be integers, not " +
                             (kind == 'f' ? "float" : kind_name(kind)) + " (got " + got(a) + ")");
    }
    require_rows(a, name, rows, width, rows_name);
    const auto n = static_cast<std::size_t>(a.size());
    std::vector<std::int64_t> out(n);
    if (kind == 'u') {
        const py::array_t<std::uint64_t, py::array::c_style | py::array::forcecast> wide(a);
        for (std::size_t k = 0; k < n; ++k) {
            const std::uint64_t v = wide.data()[k];
            if (v > static_cast<std::uint64_t>(INT64_MAX)) {
                value_error(std::string(name) + " holds " + std::to_string(v) +
                            ", beyond a 64-bit signed integer (dtype " + dtype_of(a) + ")");
            }
            out[k] = static_cast<std::int64_t>(v);
        }
    } else if (n > 0) {
        const py::array_t<std::int64_t, py::array::c_style | py::array::forcecast> wide(a);
        std::memcpy(out.data(), wide.data(), n * sizeof(std::int64_t));
    }
    return out;
}

DoubleArray pair_value_array(const py::handle& values, const char* name, py::ssize_t rows,
                             int width, const char* rows_name) {
    DoubleArray a = real_array(values, name);
    require_rows(a, name, rows, width, rows_name);
    return a;
}

namespace {

// Periodic flags of any shape as int64 0 and 1: bools, or the integers 0 and 1.
py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>
periodic_flags(const py::array& a, const char* name) {
    const char kind = a.dtype().kind();
    if (kind != 'b' && kind != 'i' && kind != 'u') {
        throw py::type_error(std::string(name) + " must be bools, not " +
                             (kind == 'f' ? "float" : kind_name(kind)) + " (got " + got(a) + ")");
    }
    py::array_t<std::int64_t, py::array::c_style | py::array::forcecast> flags(a);
    for (py::ssize_t k = 0; k < flags.size(); ++k) {
        const std::int64_t v = flags.data()[k];
        if (v != 0 && v != 1) {
            value_error(std::string(name) + " must be bools, or the integers 0 and 1 (got " +
                        std::to_string(v) + ", dtype " + dtype_of(a) + ")");
        }
    }
    return flags;
}

// The three axes from flags[first], or flags[first + k] for k < 3 (`one`: one value for all).
Periodicity axes_from(const std::int64_t* flags, bool one) {
    Periodicity pbc;
    for (std::size_t k = 0; k < 3; ++k) {
        pbc.axes[k] = flags[one ? 0 : k] == 1;
    }
    return pbc;
}

} // namespace

Periodicity periodicity(const py::handle& periodic, const char* name) {
    const py::array a = numpy_array(periodic, name);
    if (!(a.ndim() == 0 || (a.ndim() == 1 && a.shape(0) == 3))) {
        periodic_flags(a, name); // a wrong kind of value is reported first
        value_error(std::string(name) + " must be a bool or three bools (got shape " + shape_of(a) +
                    ")");
    }
    return axes_from(periodic_flags(a, name).data(), a.ndim() == 0);
}

std::vector<Periodicity> periodicities(const py::handle& periodic, std::size_t count,
                                       const char* name) {
    const py::array a = numpy_array(periodic, name);
    const auto flags = periodic_flags(a, name);
    const bool shared = a.ndim() == 0 || (a.ndim() == 1 && a.shape(0) == 3);
    if (shared) {
        return std::vector<Periodicity>(count, axes_from(flags.data(), a.ndim() == 0));
    }
    if (a.ndim() != 2 || a.shape(1) != 3 || static_cast<std::size_t>(a.shape(0)) != count) {
        value_error(std::string(name) + " must be one bool, three, or one row of three per " +
                    "structure, shape (" + std::to_string(count) + ", 3) (got shape " +
                    shape_of(a) + ")");
    }
    std::vector<Periodicity> out(count);
    for (std::size_t s = 0; s < count; ++s) {
        out[s] = axes_from(flags.data() + 3 * s, false);
    }
    return out;
}

std::vector<std::int64_t> batch_pointer(const py::handle& values, std::size_t points,
                                        const char* name) {
    const py::array a = numpy_array(values, name);
    if (a.size() == 0 && a.ndim() == 1) { // also [], which numpy makes float64
        value_error(batch_pointer_problem(nullptr, 0, points, name));
    }
    std::vector<std::int64_t> ptr = index_array(a, name, -1, 1, nullptr);
    const std::string problem = batch_pointer_problem(ptr.data(), ptr.size(), points, name);
    if (!problem.empty()) {
        value_error(problem);
    }
    return ptr;
}

DoubleArray boxes_array(const py::handle& boxes, std::size_t count, const char* name) {
    DoubleArray a = real_array(boxes, name);
    const bool empty_list = count == 0 && a.ndim() == 1 && a.size() == 0;
    if (!empty_list && (a.ndim() != 3 || static_cast<std::size_t>(a.shape(0)) != count ||
                        a.shape(1) != 3 || a.shape(2) != 3)) {
        value_error(
            std::string(name) + " must have shape (" + std::to_string(count) +
            ", 3, 3): one box per structure of batch_ptr, the lattice vectors as rows (got shape " +
            shape_of(a) + ")");
    }
    return a;
}

Box box_from_rows(const py::handle& box, const py::handle& periodic, const char* box_name,
                  const char* periodic_name) {
    const DoubleArray a = box_array(box, box_name);
    const Periodicity pbc = periodicity(periodic, periodic_name);
    Eigen::Matrix3d rows;
    for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) {
            rows(r, c) = a.at(r, c);
        }
    }
    return Box::from_rows(rows, pbc);
}

py::array checked_array(const py::handle& value, const std::string& name, const std::string& rule) {
    const char* label = name.c_str();
    if (rule == "points") {
        return points_array(value, label);
    }
    if (rule == "box") {
        return box_array(value, label);
    }
    if (rule == "real") {
        return real_array(value, label);
    }
    if (rule == "species") {
        const std::vector<std::int32_t> values = species_array(value, label);
        return py::array_t<std::int32_t>(static_cast<py::ssize_t>(values.size()), values.data());
    }
    if (rule == "periodic") {
        const Periodicity pbc = periodicity(value, label);
        py::array_t<bool> out(3);
        for (std::size_t k = 0; k < 3; ++k) {
            out.mutable_data()[k] = pbc.axes[k];
        }
        return std::move(out);
    }
    value_error("rule must be \"points\", \"box\", \"real\", \"species\" or \"periodic\" (got \"" +
                rule + "\")");
}

std::string described(const py::handle& value) {
    try {
        const std::string text = py::repr(value).cast<std::string>();
        return text.size() > 80 ? text.substr(0, 77) + "..." : text;
    } catch (const py::error_already_set&) {
        return std::string("a ") + Py_TYPE(value.ptr())->tp_name;
    }
}

void set_cutoff(const py::object& cutoff, NeighborOptions& options) {
    if (py::isinstance<py::dict>(cutoff)) {
        for (const auto& entry : cutoff.cast<py::dict>()) {
            try {
                const auto key = entry.first.cast<std::pair<std::int32_t, std::int32_t>>();
                options.species_cutoffs.push_back(
                    SpeciesCutoff{key.first, key.second, entry.second.cast<double>()});
            } catch (const py::cast_error&) {
                throw py::value_error("a cutoff dict maps pairs of integer species to "
                                      "cutoffs (got " +
                                      py::repr(entry.first).cast<std::string>() + ": " +
                                      py::repr(entry.second).cast<std::string>() + ")");
            }
        }
        if (options.species_cutoffs.empty()) {
            throw py::value_error("the cutoff dict of species pairs is empty");
        }
    } else if (!cutoff.is_none()) {
        try {
            options.cutoff = cutoff.cast<double>();
        } catch (const py::cast_error&) {
            throw py::value_error("cutoff must be a number, a dict of species pairs or None "
                                  "(got " +
                                  py::repr(cutoff).cast<std::string>() + ")");
        }
    }
}

std::size_t max_bytes_argument(const py::object& value) {
    if (value.is_none()) {
        return NeighborOptions().max_bytes;
    }
    if (py::isinstance<py::int_>(value) && !py::isinstance<py::bool_>(value)) {
        try {
            return value.cast<std::size_t>();
        } catch (const py::cast_error&) {
            // negative or past 2^64: refused below
        }
    }
    throw py::value_error("max_bytes must be a whole number of bytes >= 0 (0: no limit) or None "
                          "(three quarters of the memory this process may use), got " +
                          described(value));
}

} // namespace tricell::python
