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

// A column buffer owned by the arrays' capsule, given back to its recycler when they are gone.
template <class T> struct OwnedColumn {
    PairArray<T> data;
    PairArray<T> PairColumns::*which;
    std::weak_ptr<ColumnRecycler> home;
};

// An array of the `width`-wide rows of `column`, which it takes over (no copy).
template <class T>
py::array owned_column(PairArray<T>& column, PairArray<T> PairColumns::*which, std::size_t width,
                       const std::shared_ptr<ColumnRecycler>& recycler) {
    std::vector<py::ssize_t> shape{static_cast<py::ssize_t>(column.size() / width)};
    if (width > 1) {
        shape.push_back(static_cast<py::ssize_t>(width));
    }
    auto* owned = new OwnedColumn<T>{std::move(column), which, recycler};
    py::capsule base(owned, [](void* p) {
        auto* c = static_cast<OwnedColumn<T>*>(p);
        if (const std::shared_ptr<ColumnRecycler> home = c->home.lock()) {
            home->give_back(c->which, c->data);
        }
        delete c;
    });
    return py::array_t<T>(shape, owned->data.data(), base);
}

} // namespace

py::object pair_columns(const NeighborList& list, const QuantitySpec& spec,
                        const std::shared_ptr<const NeighborList>& owner) {
    return columns_of(list, spec, keeper(owner));
}

template <class T>
void ColumnRecycler::give_back(PairArray<T> PairColumns::*which, PairArray<T>& column) {
    std::lock_guard<std::mutex> lock(mutex_);
    PairArray<T>& spare = spare_.*which;
    if (column.capacity() > spare.capacity()) {
        column.clear();
        spare.swap(column);
    }
}

void ColumnRecycler::lend(BatchList& list) {
    PairColumns columns;
    list.swap_columns(columns);
    {
        std::lock_guard<std::mutex> lock(mutex_);
        const auto lend_one = [](auto& to, auto& from) {
            if (from.capacity() > to.capacity()) {
                to.swap(from);
            }
        };
        lend_one(columns.i, spare_.i);
        lend_one(columns.j, spare_.j);
        lend_one(columns.shifts, spare_.shifts);
        lend_one(columns.distances, spare_.distances);
        lend_one(columns.vectors, spare_.vectors);
    }
    list.swap_columns(columns);
}

py::tuple batch_columns(BatchList& list, const QuantitySpec& spec,
                        const std::shared_ptr<const BatchList>& owner,
                        const std::shared_ptr<ColumnRecycler>& recycler) {
    const std::vector<std::size_t>& offsets = list.pair_offsets();
    py::array_t<std::int64_t> pair_offsets(static_cast<py::ssize_t>(offsets.size()));
    for (std::size_t s = 0; s < offsets.size(); ++s) {
        pair_offsets.mutable_data()[s] = static_cast<std::int64_t>(offsets[s]);
    }
    const std::size_t count = spec.columns.size();
    py::tuple out(1 + count);
    out[0] = pair_offsets;
    if (owner || list.size() == 0) {
        py::object columns = columns_of(list, spec, keeper(owner));
        for (std::size_t k = 0; k < count; ++k) {
            out[k + 1] = count == 1 ? columns : py::object(columns.cast<py::tuple>()[k]);
        }
        return out;
    }
    // P and o first (fresh arrays built from the columns), then each asked column taken over
    // once (a letter asked again is a copy of the first array).
    QuantitySpec rest;
    for (std::size_t k = 0; k < count; ++k) {
        const Column c = spec.columns[k];
        if (c == Column::pairs || c == Column::offsets) {
            rest.columns.assign(1, c);
            out[k + 1] = columns_of(list, rest, py::object());
        }
    }
    PairColumns taken;
    list.swap_columns(taken);
    std::vector<std::pair<Column, py::object>> given;
    for (std::size_t k = 0; k < count; ++k) {
        const Column c = spec.columns[k];
        if (c == Column::pairs || c == Column::offsets) {
            continue;
        }
        const auto first = std::find_if(given.begin(), given.end(),
                                        [c](const auto& entry) { return entry.first == c; });
        if (first != given.end()) {
            out[k + 1] = first->second.attr("copy")();
            continue;
        }
        py::array a;
        switch (c) {
        case Column::i:
            a = owned_column(taken.i, &PairColumns::i, 1, recycler);
            break;
        case Column::j:
            a = owned_column(taken.j, &PairColumns::j, 1, recycler);
            break;
        case Column::shifts:
            a = owned_column(taken.shifts, &PairColumns::shifts, 3, recycler);
            break;
        case Column::distances:
            a = owned_column(taken.distances, &PairColumns::distances, 1, recycler);
            break;
        case Column::vectors:
            a = owned_column(taken.vectors, &PairColumns::vectors, 3, recycler);
            break;
        default:
            break;
        }
        given.emplace_back(c, a);
        out[k + 1] = a;
    }
    list.swap_columns(taken); // what was not asked for stays with the list
    return out;
}

} // namespace tricell::python
