// verify(): a list against the reference search (reference.cpp) and the list rules. Each entry
// is first checked on its own, in list order (indices in range, no (i, i, 0), S = 0 along open
// axes, d and D equal to those recomputed from the caller's positions); a half list's entries are
// then turned into the half orientation (i < j, or i == j with S positive), so that either
// orientation of a pair is accepted. The entries, sorted by (i, j, S), are merged with the
// reference's sorted pairs: equal neighbours are duplicates, a key only the list has is extra
// and one only the reference has is missing, unless its distance is within rounding of its
// cutoff (rounding_allowance()).
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <vector>

#include "search/options.hpp"
#include "tricell/error.hpp"
#include "tricell/verify.hpp"
#include "verify/reference.hpp"

namespace tricell {

namespace {

using detail::PairKey;

// One entry of the list under test, in the half orientation for a half list.
struct Entry {
    PairKey key;
    std::size_t index; // position in the list
    bool turned;       // a half-list entry given as (j, i, -S)
};

// (The streams throw std::bad_alloc rather than lose text when memory runs out.)
std::string describe(const PairKey& key) {
    std::ostringstream out;
    out.exceptions(std::ios::badbit);
    out << "(" << key[0] << ", " << key[1] << ", [" << key[2] << " " << key[3] << " " << key[4]
        << "])";
    return out.str();
}

std::string number(double value) {
    std::ostringstream out;
    out.exceptions(std::ios::badbit);
    out.precision(6);
    out << value;
    return out.str();
}

const char* axis_name(int axis) {
    return axis == 0 ? "a" : axis == 1 ? "b" : "c";
}

// The verdict being built: counts, and the first difference in words.
class Verdict {
  public:
    explicit Verdict(VerifyReport& report) : report_(report) {}
    void note(std::size_t& count, const std::string& what) {
        ++count;
        if (report_.message.empty()) {
            report_.message = what;
        }
    }

  private:
    VerifyReport& report_;
};

// The list's arrays behind one interface: the int64 arrays of PairArrays, or a NeighborList.
struct Columns {
    std::size_t size;
    std::int64_t (*i)(const void*, std::size_t);
    std::int64_t (*j)(const void*, std::size_t);
    std::int64_t (*shift)(const void*, std::size_t, int); // null: all zero
    const double* distances;
    const double* vectors;
    const void* source;
};

VerifyReport check(const Box& box, PointsView x, const NeighborOptions& options,
                   const Columns& list) {
    options.validate();
    if (options.max_neighbors != 0) {
        detail::fail<InvalidArgument>("verify() checks a whole list within the cutoff: "
                                      "max_neighbors cannot be asked of it");
    }
    detail::check_positions(x, 1);
    const std::size_t n = x.size();
    if (!options.radii.empty() && options.radii.size() != n) {
        detail::fail<InvalidArgument>("radii has ", options.radii.size(), " entries for ", n,
                                      " positions");
    }
    if (!options.species_cutoffs.empty() && options.species.size() != n) {
        detail::fail<InvalidArgument>("species has ", options.species.size(), " entries for ", n,
                                      " positions");
    }
    if (list.shift == nullptr && box.periodicity().any() && list.size > 0) {
        detail::fail<InvalidArgument>(
            "the list has no shifts S, which a box periodic along any axis needs");
    }
    const detail::PairCutoff cutoff_of(options);
    VerifyReport report;
    Verdict verdict(report);
    report.entries = list.size;
    const Eigen::Matrix3d& h = box.matrix();
    const std::int64_t shift_bound = std::int64_t(1) << 30;

    std::vector<Entry> entries;
    entries.reserve(list.size);
    for (std::size_t k = 0; k < list.size; ++k) {
        PairKey key{list.i(list.source, k), list.j(list.source, k), 0, 0, 0};
        for (int axis = 0; axis < 3 && list.shift != nullptr; ++axis) {
            key[std::size_t(2 + axis)] = list.shift(list.source, k, axis);
        }
        const std::string entry = "entry " + std::to_string(k) + " " + describe(key);
        if (key[0] < 0 || key[0] >= std::int64_t(n) || key[1] < 0 || key[1] >= std::int64_t(n)) {
            verdict.note(
                report.rule_breaks,
                entry + ": index " +
                    std::to_string(key[0] < 0 || key[0] >= std::int64_t(n) ? key[0] : key[1]) +
                    " is out of range for " + std::to_string(n) + " positions");
            continue;
        }
        bool broken = false;
        for (int axis = 0; axis < 3 && !broken; ++axis) {
            const std::int64_t s = key[std::size_t(2 + axis)];
            if (!box.periodic(axis) && s != 0) {
                verdict.note(report.rule_breaks, entry + ": a shift along the open axis " +
                                                     axis_name(axis) + " (S" + axis_name(axis) +
                                                     " = " + std::to_string(s) + ")");
                broken = true;
            } else if (s <= -shift_bound || s >= shift_bound) {
                verdict.note(report.rule_breaks, entry + ": shift S" + axis_name(axis) + " = " +
                                                     std::to_string(s) + " is out of range");
                broken = true;
            }
        }
        if (broken) {
            continue;
        }
        if (key[0] == key[1] && key[2] == 0 && key[3] == 0 && key[4] == 0) {
            verdict.note(report.rule_breaks, entry + ": an atom paired with itself");
            continue;
        }
        const std::size_t i = std::size_t(key[0]), j = std::size_t(key[1]);
        const Eigen::Vector3i shift{int(key[2]), int(key[3]), int(key[4])};
        const Eigen::Vector3d d = x[j] - x[i] + h * shift.cast<double>();
        const double tol = rounding_allowance(box, x[i], x[j], shift, cutoff_of(i, j));
        if (list.distances != nullptr && !(std::abs(list.distances[k] - d.norm()) <= tol)) {
            verdict.note(report.wrong_values, entry + ": distance " + number(list.distances[k]) +
                                                  " but the positions give " + number(d.norm()));
        } else if (list.vectors != nullptr &&
                   !((Eigen::Map<const Eigen::Vector3d>(list.vectors + 3 * k) - d).norm() <= tol)) {
            const double* v = list.vectors + 3 * k;
            verdict.note(report.wrong_values, entry + ": vector [" + number(v[0]) + " " +
                                                  number(v[1]) + " " + number(v[2]) +
                                                  "] but the positions give [" + number(d[0]) +
                                                  " " + number(d[1]) + " " + number(d[2]) + "]");
        }
        const bool turned = options.half && !detail::canonical_orientation(key);
        if (turned) {
            key = PairKey{key[1], key[0], -key[2], -key[3], -key[4]};
        }
        entries.push_back(Entry{key, k, turned});
    }

    detail::ReferencePairs reference = detail::reference_pairs(box, x, options, cutoff_of);
    // A list of a query's pairs: the reference's pairs with i in the query (full), or with
    // either end in it (half; the entries are compared canonically oriented, as above).
    const std::vector<std::uint8_t> in_query = detail::query_flags(options, n);
    if (!in_query.empty()) {
        const auto outside = [&](const PairKey& key) {
            return !in_query[std::size_t(key[0])] &&
                   (!options.half || !in_query[std::size_t(key[1])]);
        };
        reference.keys.erase(std::remove_if(reference.keys.begin(), reference.keys.end(), outside),
                             reference.keys.end());
    }
    report.reference = reference.method;
    report.expected = reference.keys.size();
    std::stable_sort(entries.begin(), entries.end(),
                     [](const Entry& a, const Entry& b) { return a.key < b.key; });

    // The distance of a key, its cutoff and whether rounding may decide it.
    struct Judged {
        double distance;
        double cutoff;
        bool near;
    };
    const auto judge = [&](const PairKey& key) {
        const std::size_t i = std::size_t(key[0]), j = std::size_t(key[1]);
        const Eigen::Vector3i shift{int(key[2]), int(key[3]), int(key[4])};
        const double d = (x[j] - x[i] + h * shift.cast<double>()).norm();
        const double c = cutoff_of(i, j);
        return Judged{d, c, std::abs(d - c) <= rounding_allowance(box, x[i], x[j], shift, c)};
    };
    std::size_t r = 0;
    for (std::size_t e = 0; e < entries.size(); ++e) {
        const Entry& entry = entries[e];
        if (e > 0 && entries[e - 1].key == entry.key) {
            const Entry& first = entries[e - 1];
            std::string what = "pair " + describe(entry.key) + " is listed twice (entries " +
                               std::to_string(first.index) + " and " + std::to_string(entry.index) +
                               ")";
            if (first.turned != entry.turned) {
                what += ", in both orientations; a half list holds each pair once";
            }
            verdict.note(report.duplicates, what);
            continue;
        }
        while (r < reference.keys.size() && reference.keys[r] < entry.key) {
            const Judged judged = judge(reference.keys[r]);
            if (judged.near) {
                ++report.near_cutoff;
            } else {
                verdict.note(report.missing, "pair " + describe(reference.keys[r]) +
                                                 " at distance " + number(judged.distance) +
                                                 " < cutoff " + number(judged.cutoff) +
                                                 " is missing");
            }
            ++r;
        }
        if (r < reference.keys.size() && reference.keys[r] == entry.key) {
            ++report.matched;
            ++r;
            continue;
        }
        const Judged judged = judge(entry.key);
        if (judged.near) {
            ++report.near_cutoff;
        } else if (judged.distance >= judged.cutoff) {
            verdict.note(report.extra, "pair " + describe(entry.key) + " (entry " +
                                           std::to_string(entry.index) + ") at distance " +
                                           number(judged.distance) + " >= cutoff " +
                                           number(judged.cutoff) + " is not a pair");
        } else {
            verdict.note(report.extra,
                         "pair " + describe(entry.key) + " (entry " + std::to_string(entry.index) +
                             ") at distance " + number(judged.distance) + " < cutoff " +
                             number(judged.cutoff) + " is not found by " + reference.method);
        }
    }
    for (; r < reference.keys.size(); ++r) {
        const Judged judged = judge(reference.keys[r]);
        if (judged.near) {
            ++report.near_cutoff;
        } else {
            verdict.note(report.missing, "pair " + describe(reference.keys[r]) + " at distance " +
                                             number(judged.distance) + " < cutoff " +
                                             number(judged.cutoff) + " is missing");
        }
    }
    report.ok = report.message.empty();
    if (report.ok) {
        report.message = "ok: " + std::to_string(report.entries) + " entries match " +
                         std::to_string(report.expected) + " pairs of " + reference.method +
                         (options.half ? " (half list)" : " (full list)");
        if (report.near_cutoff > 0) {
            report.message +=
                ", " + std::to_string(report.near_cutoff) + " within rounding of the cutoff";
        }
    }
    return report;
}

std::int64_t array_i(const void* source, std::size_t k) {
    return static_cast<const PairArrays*>(source)->i[k];
}
std::int64_t array_j(const void* source, std::size_t k) {
    return static_cast<const PairArrays*>(source)->j[k];
}
std::int64_t array_shift(const void* source, std::size_t k, int axis) {
    return static_cast<const PairArrays*>(source)->shifts[3 * k + std::size_t(axis)];
}
std::int64_t list_i(const void* source, std::size_t k) {
    return static_cast<const NeighborList*>(source)->i()[k];
}
std::int64_t list_j(const void* source, std::size_t k) {
    return static_cast<const NeighborList*>(source)->j()[k];
}
std::int64_t list_shift(const void* source, std::size_t k, int axis) {
    return static_cast<const NeighborList*>(source)->shifts()[3 * k + std::size_t(axis)];
}

} // namespace

VerifyReport verify(const Box& box, PointsView positions, const NeighborOptions& options,
                    const PairArrays& list) {
    if (list.size > 0 && (list.i == nullptr || list.j == nullptr)) {
        detail::fail<InvalidArgument>("the list has ", list.size, " entries but ",
                                      list.i == nullptr ? "i" : "j", " is null");
    }
    const Columns columns{
        list.size,      array_i,      array_j, list.shifts != nullptr ? array_shift : nullptr,
        list.distances, list.vectors, &list};
    return check(box, positions, options, columns);
}

VerifyReport verify(const Box& box, PointsView positions, const NeighborOptions& options,
                    const NeighborList& list) {
    const std::size_t size = list.size();
    const Columns columns{size,
                          list_i,
                          list_j,
                          list.shifts().size() == 3 * size ? list_shift : nullptr,
                          list.distances().size() == size ? list.distances().data() : nullptr,
                          list.vectors().size() == 3 * size ? list.vectors().data() : nullptr,
                          &list};
    return check(box, positions, options, columns);
}

} // namespace tricell
