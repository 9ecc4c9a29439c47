// Test support for tricell::mpi: gathering every rank's pairs onto rank 0 and comparing them with
// the serial list of the same atoms, with the verdict shared by all ranks (so that every rank
// takes the same branch and no collective is left waiting).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include <mpi.h>

#include "tricell/mpi.hpp"
#include "tricell/neighbor_list.hpp"

namespace tricell::testing {

inline int world_rank() {
    int r = 0;
    MPI_Comm_rank(MPI_COMM_WORLD, &r);
    return r;
}
inline int world_size() {
    int s = 1;
    MPI_Comm_size(MPI_COMM_WORLD, &s);
    return s;
}

/// Concatenation on rank 0 of every rank's doubles (empty elsewhere).
inline std::vector<double> gather_to_root(const std::vector<double>& mine, MPI_Comm comm) {
    int size = 1, rank = 0;
    MPI_Comm_size(comm, &size);
    MPI_Comm_rank(comm, &rank);
    int count = int(mine.size());
    std::vector<int> counts(static_cast<std::size_t>(size)), offsets(counts.size(), 0);
    MPI_Gather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, comm);
    for (int r = 1; r < size; ++r) {
        offsets[std::size_t(r)] = offsets[std::size_t(r) - 1] + counts[std::size_t(r) - 1];
    }
    std::vector<double> all(rank == 0 ? std::size_t(offsets.back() + counts.back()) : 0);
    MPI_Gatherv(mine.data(), count, MPI_DOUBLE, all.data(), counts.data(), offsets.data(),
                MPI_DOUBLE, 0, comm);
    return all;
}

/// Rank 0's verdict (empty = pass) on every rank.
inline std::string share_verdict(const std::string& verdict, MPI_Comm comm) {
    int length = int(verdict.size());
    MPI_Bcast(&length, 1, MPI_INT, 0, comm);
    std::string out(std::size_t(length), ' ');
    if (world_rank() == 0) {
        out = verdict;
    }
    MPI_Bcast(out.data(), length, MPI_CHAR, 0, comm);
    return out;
}

/// True on every rank when every rank holds the same boundaries.
inline bool agreed_bounds(const mpi::Decomposition& d) {
    std::vector<double> mine;
    for (int axis = 0; axis < 3; ++axis) {
        mine.insert(mine.end(), d.bounds(axis).begin(), d.bounds(axis).end());
    }
    std::vector<double> root = mine;
    MPI_Bcast(root.data(), int(root.size()), MPI_DOUBLE, 0, d.comm());
    int same = root == mine, all = 0;
    MPI_Allreduce(&same, &all, 1, MPI_INT, MPI_MIN, d.comm());
    return all == 1;
}

/// Every rank's atoms (id, caller position) gathered on rank 0 into id order.
inline std::vector<Eigen::Vector3d> gather_positions(const mpi::LocalAtoms& atoms, MPI_Comm comm) {
    std::vector<double> mine;
    for (std::size_t a = 0; a < atoms.size(); ++a) {
        mine.insert(mine.end(), {double(atoms.ids[a]), atoms.positions[3 * a],
                                 atoms.positions[3 * a + 1], atoms.positions[3 * a + 2]});
    }
    const std::vector<double> all = gather_to_root(mine, comm);
    std::vector<Eigen::Vector3d> x(all.size() / 4);
    for (std::size_t k = 0; k < x.size(); ++k) {
        const auto id = std::size_t(all[4 * k]);
        if (id < x.size()) {
            x[id] = Eigen::Vector3d(all[4 * k + 1], all[4 * k + 2], all[4 * k + 3]);
        }
    }
    return x;
}

/// The serial half list's orientation: i < j, or i == j with S lexicographically positive.
inline bool canonical(std::uint64_t i, std::uint64_t j, const std::int32_t* s) {
    if (i != j) {
        return i < j;
    }
    return s[0] > 0 || (s[0] == 0 && (s[1] > 0 || (s[1] == 0 && s[2] > 0)));
}

/// Compares the union of the ranks' pairs (i, j, S, d, D required) with the serial list of the
/// gathered atoms: the same set of (i, j, S), no (i, j, S) twice, and the same d and D to 1e-9
/// relative. A half list's pairs are compared in the serial orientation (a pair with a ghost end
/// is oriented from its owned end), and one whose ends are both owned must have it already.
/// Returns "" on every rank when they agree, else rank 0's description.
inline std::string compare_with_serial(const mpi::DistributedPairs& pairs,
                                       const mpi::LocalAtoms& atoms, const Box& box,
                                       const NeighborOptions& options, MPI_Comm comm) {
    std::vector<double> mine;
    mine.reserve(9 * pairs.size());
    for (std::size_t k = 0; k < pairs.size(); ++k) {
        const std::int32_t* s = &pairs.shifts[3 * k];
        const bool flip = options.half && !canonical(pairs.i[k], pairs.j[k], s);
        const double sign = flip ? -1.0 : 1.0;
        const std::uint64_t i = flip ? pairs.j[k] : pairs.i[k];
        const std::uint64_t j = flip ? pairs.i[k] : pairs.j[k];
        mine.insert(mine.end(), {double(i), double(j), sign * s[0], sign * s[1], sign * s[2],
                                 pairs.distances[k], sign * pairs.vectors[3 * k],
                                 sign * pairs.vectors[3 * k + 1], sign * pairs.vectors[3 * k + 2]});
        if (atoms.ids[pairs.owned[k]] != pairs.i[k] || (flip && pairs.local_j[k] < atoms.size())) {
            // The owned index does not name i, or an owned-owned pair is not in the serial
            // orientation: reported below as a wrong D.
            mine.back() = std::nan("");
        }
    }
    const std::vector<double> all = gather_to_root(mine, comm);
    const std::vector<Eigen::Vector3d> x = gather_positions(atoms, comm);
    std::string verdict;
    if (world_rank() == 0) {
        using Key = std::tuple<long, long, int, int, int>;
        NeighborOptions serial_options = options;
        serial_options.quantities = Quantities{true, true, true};
        serial_options.sorted = false;
        const NeighborList serial = compute_neighbors(box, x, serial_options);
        std::map<Key, std::size_t> expected;
        for (std::size_t k = 0; k < serial.size(); ++k) {
            const Shift s = serial.shift(k);
            expected[Key{long(serial.i()[k]), long(serial.j()[k]), s[0], s[1], s[2]}] = k;
        }
        std::map<Key, int> seen;
        std::ostringstream out;
        int problems = 0;
        for (std::size_t k = 0; 9 * k < all.size(); ++k) {
            const double* p = &all[9 * k];
            const Key key{long(p[0]), long(p[1]), int(p[2]), int(p[3]), int(p[4])};
            auto describe = [&] {
                return "(" + std::to_string(std::get<0>(key)) + ", " +
                       std::to_string(std::get<1>(key)) + ", [" + std::to_string(std::get<2>(key)) +
                       " " + std::to_string(std::get<3>(key)) + " " +
                       std::to_string(std::get<4>(key)) + "])";
            };
            if (++seen[key] == 2 && problems++ < 5) {
                out << "pair " << describe() << " reported twice; ";
            }
            const auto it = expected.find(key);
            if (it == expected.end()) {
                if (problems++ < 5) {
                    out << "pair " << describe() << " is not in the serial list (d = " << p[5]
                        << "); ";
                }
                continue;
            }
            const std::size_t s = it->second;
            const Eigen::Vector3d d(p[6], p[7], p[8]);
            const double scale = 1e-9 * std::max(1.0, serial.distances()[s]);
            if (!(std::abs(p[5] - serial.distances()[s]) < scale &&
                  (d - serial.vector(s)).norm() < scale)) {
                if (problems++ < 5) {
                    out << "pair " << describe() << " has d = " << p[5] << ", serial "
                        << serial.distances()[s] << "; ";
                }
            }
        }
        for (const auto& [key, k] : expected) {
            if (seen.count(key) == 0 && problems++ < 5) {
                out << "serial pair (" << std::get<0>(key) << ", " << std::get<1>(key) << ", ["
                    << std::get<2>(key) << " " << std::get<3>(key) << " " << std::get<4>(key)
                    << "]) d = " << serial.distances()[k] << " is missing; ";
            }
        }
        if (problems > 0) {
            out << problems << " problems; " << all.size() / 9 << " pairs reported, "
                << serial.size() << " serial";
            verdict = out.str();
        }
    }
    return share_verdict(verdict, comm);
}

/// The atoms of a global system dealt round-robin (atom g to rank g % size), not yet migrated.
inline mpi::LocalAtoms deal(const std::vector<Eigen::Vector3d>& x, int payload_width = 0) {
    mpi::LocalAtoms atoms;
    atoms.payload_width = std::size_t(payload_width);
    for (std::size_t g = 0; g < x.size(); ++g) {
        if (int(g % std::size_t(world_size())) == world_rank()) {
            atoms.ids.push_back(g);
            atoms.positions.insert(atoms.positions.end(), {x[g][0], x[g][1], x[g][2]});
            for (int k = 0; k < payload_width; ++k) {
                atoms.payload.push_back(double(g) * 10 + k);
            }
        }
    }
    return atoms;
}

} // namespace tricell::testing
