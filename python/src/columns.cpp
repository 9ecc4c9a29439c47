// The quantity letters read into a QuantitySpec, and the numpy arrays of a list's columns built
// from it (views or copies); the rules are in columns.hpp.
#include "columns.hpp"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <utility>

#include <pybind11/numpy.h>

namespace tricell::python {

namespace {

// Every letter a quantities argument takes, the column it names and, for S, d and D, the
// column the search stores for it.
struct Letter {
    char letter;
    Column column;
    bool Quantities::*stored;
};

constexpr Letter letters_table[] = {
    {'i', Column::i, nullptr},
    {'j', Column::j, nullptr},
    {'S', Column::shifts, &Quantities::shifts},
    {'d', Column::distances, &Quantities::distances},
    {'D', Column::vectors, &Quantities::vectors},
    {'P', Column::pairs, nullptr},
    {'o', Column::offsets, nullptr},
};

// "i, j, S, d, D, P, o": the letters of the table, for messages.
std::string letter_names() {
    std::string text;
    for (const Letter& entry : letters_table) {
        text += std::string(text.empty() ? "" : ", ") + entry.letter;
    }
    return text;
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

// The columns of a list or of a batch's lists (the same accessors), views on `base` when it is
// set, copies otherwise.
template <class List>
py::object columns_of(const List& list, const QuantitySpec& spec, const py::object& base) {
    const std::size_t n = list.size();
    py::tuple out(spec.columns.size());
    for (std::size_t k = 0; k < spec.columns.size(); ++k) {
        py::array a;
        switch (spec.columns[k]) {
        case Column::i:
            a = column(list.i().data(), n, 1, base);
            break;
        case Column::j:
            a = column(list.j().data(), n, 1, base);
            break;
        case Column::shifts:
            a = column(list.shifts().data(), n, 3, base);
            break;
        case Column::distances:
            a = column(list.distances().data(), n, 1, base);
            break;
        case Column::vectors:
            a = column(list.vectors().data(), n, 3, base);
            break;
        case Column::pairs: {
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
        case Column::offsets: {
            const std::vector<std::size_t>& offsets = list.offsets();
            py::array_t<std::int64_t> copy(static_cast<py::ssize_t>(offsets.size()));
            std::copy(offsets.begin(), offsets.end(), copy.mutable_data());
            a = copy;
            break;
        }
        }
        out[k] = a;
    }
    if (spec.columns.size() == 1) {
        return out[0];
    }
    return std::move(out);
}

} // namespace

QuantitySpec parse_quantities(const std::string& letters) {
    QuantitySpec spec;
    spec.stored.shifts = spec.stored.distances = spec.stored.vectors = false;
    for (const char letter : letters) {
        const auto* entry =
            std::find_if(std::begin(letters_table), std::end(letters_table),
                         [letter](const Letter& candidate) { return candidate.letter == letter; });
        if (entry == std::end(letters_table)) {
            throw py::value_error("unknown quantity '" + std::string(1, letter) +
                                  "' in quantities='" + letters + "' (expected letters among " +
                                  letter_names() + ")");
        }
        spec.columns.push_back(entry->column);
        if (entry->stored != nullptr) {
            spec.stored.*(entry->stored) = true;
        }
        spec.offsets = spec.offsets || entry->column == Column::offsets;
    }
    if (letters.empty()) {
        throw py::value_error("quantities must name at least one of " + letter_names() +
                              " (got '')");
    }
    return spec;
}

namespace {

// A capsule holding a reference to `owner`: the base of the views of its buffers.
template <class List> py::object keeper(const std::shared_ptr<const List>& owner) {
    if (!owner) {
        return py::object();
    }
    auto* keep = new std::shared_ptr<const List>(owner);
    return py::capsule(keep, [](void* p) { delete static_cast<std::shared_ptr<const List>*>(p); });
}

// i or j of a batch with each structure's first atom added: indices into all its atoms.
py::array global_indices(const BatchList& list, const PairArray<std::uint32_t>& local) {
    py::array_t<std::uint32_t> out(static_cast<py::ssize_t>(list.size()));
    std::uint32_t* to = out.mutable_data();
    const std::vector<std::size_t>& pairs = list.pair_offsets();
    const std::vector<std::size_t>& atoms = list.atom_offsets();
    for (std::size_t s = 0; s + 1 < pairs.size(); ++s) {
        const auto first = static_cast<std::uint32_t>(atoms[s]);
        for (std::size_t k = pairs[s]; k < pairs[s + 1]; ++k) {
            to[k] = local[k] + first;
        }
    }
    return std::move(out);
}

} // namespace

py::object pair_columns(const NeighborList& list, const QuantitySpec& spec,
                        const std::shared_ptr<const NeighborList>& owner) {
    return columns_of(list, spec, keeper(owner));
}

py::tuple batch_columns(const BatchList& list, const QuantitySpec& spec,
                        const std::shared_ptr<const BatchList>& owner, bool global) {
    const std::vector<std::size_t>& offsets = list.pair_offsets();
    py::array_t<std::int64_t> pair_offsets(static_cast<py::ssize_t>(offsets.size()));
    for (std::size_t s = 0; s < offsets.size(); ++s) {
        pair_offsets.mutable_data()[s] = static_cast<std::int64_t>(offsets[s]);
    }
    const std::size_t count = spec.columns.size();
    py::object columns = columns_of(list, spec, keeper(owner));
    py::tuple out(1 + count);
    out[0] = pair_offsets;
    for (std::size_t k = 0; k < count; ++k) {
        py::object column = count == 1 ? columns : py::object(columns.cast<py::tuple>()[k]);
        if (global && spec.columns[k] == Column::i) {
            column = global_indices(list, list.i());
        } else if (global && spec.columns[k] == Column::j) {
            column = global_indices(list, list.j());
        } else if (global && spec.columns[k] == Column::pairs) {
            const py::array_t<std::uint32_t> i = global_indices(list, list.i());
            const py::array_t<std::uint32_t> j = global_indices(list, list.j());
            py::array_t<std::uint32_t> pairs(
                std::vector<py::ssize_t>{static_cast<py::ssize_t>(list.size()), 2});
            for (std::size_t m = 0; m < list.size(); ++m) {
                pairs.mutable_data()[2 * m] = i.data()[m];
                pairs.mutable_data()[2 * m + 1] = j.data()[m];
            }
            column = pairs;
        }
        out[k + 1] = column;
    }
    return out;
}

} // namespace tricell::python
