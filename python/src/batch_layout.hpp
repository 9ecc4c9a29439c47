// The concatenated batch layout of machine-learning codes, as both Python fronts take it (the
// numpy module's compute_batch and the PyTorch op library's batch op): the positions of all
// structures one after the other, a pointer array (B + 1 entries: structure s owns rows
// ptr[s]:ptr[s + 1]) and one box per structure. Header-only, free of pybind11 and torch, so each
// front phrases the same rule in its own argument names.
#pragma once

#include <cctype>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>

namespace tricell::python {

/// Why ptr[0..entries) is no pointer array over `points` rows, in words naming `name` (it
/// must have at least one entry, start at 0, never decrease and end at `points`); empty when it
/// is one.
inline std::string batch_pointer_problem(const std::int64_t* ptr, std::size_t entries,
                                         std::size_t points, const std::string& name) {
    const auto at = [&](std::size_t k) {
        return name + "[" + std::to_string(k) + "] = " + std::to_string(ptr[k]);
    };
    if (entries == 0) {
        return name + " must have B + 1 entries for B structures, at least one (got an empty " +
               "array)";
    }
    if (ptr[0] != 0) {
        return name + " must start at 0 (got " + at(0) + ")";
    }
    for (std::size_t s = 0; s + 1 < entries; ++s) {
        if (ptr[s + 1] < ptr[s]) {
            return name + " must not decrease (got " + at(s) + " > " + at(s + 1) + ": structure " +
                   std::to_string(s) + " would have " + std::to_string(ptr[s + 1] - ptr[s]) +
                   " atoms)";
        }
    }
    if (static_cast<std::uint64_t>(ptr[entries - 1]) != points) {
        return name + " must end at the number of points, " + std::to_string(points) + " (got " +
               at(entries - 1) + ")";
    }
    return std::string();
}

/// Whether structure s > 0 has the very cell of structure s - 1 (`cells`: 9 doubles, the rows,
/// per structure), bit for bit: with the same periodicity, the box built for s - 1 then serves
/// s as it is (molecules of a data set all come with the same all-zero cell), and a front
/// builds it once.
inline bool same_cell_as_previous(const double* cells, std::size_t s) {
    return s > 0 && std::memcmp(cells + 9 * s, cells + 9 * (s - 1), 9 * sizeof(double)) == 0;
}

/// A library message about one structure of a batch ("structure S: ..."), with the rows of the
/// concatenated positions that structure owns: "structure 3, points[100:110]: position 2 is not
/// finite (...)", `points` naming the positions argument. Other messages are returned as they
/// are.
inline std::string with_rows_of(const std::string& message, const std::int64_t* ptr,
                                std::size_t entries, const std::string& points) {
    const std::string prefix = "structure ";
    std::size_t end = prefix.size();
    while (end < message.size() && std::isdigit(static_cast<unsigned char>(message[end]))) {
        ++end;
    }
    if (message.compare(0, prefix.size(), prefix) != 0 || end == prefix.size() ||
        message.compare(end, 2, ": ") != 0 || end - prefix.size() > 18) {
        return message;
    }
    const std::size_t s = std::stoull(message.substr(prefix.size(), end - prefix.size()));
    if (s + 1 >= entries) {
        return message;
    }
    return message.substr(0, end) + ", " + points + "[" + std::to_string(ptr[s]) + ":" +
           std::to_string(ptr[s + 1]) + "]" + message.substr(end);
}

} // namespace tricell::python
