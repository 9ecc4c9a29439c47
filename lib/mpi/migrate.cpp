// migrate(): every atom to the owner of its wrapped fractional position (see atoms.hpp).
#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <numeric>
#include <string>

#include "collective.hpp"
#include "tricell/error.hpp"
#include "tricell/mpi/atoms.hpp"

namespace tricell::mpi {

using tricell::detail::fail;

void LocalAtoms::validate() const {
    const std::size_t n = ids.size();
    if (positions.size() != 3 * n) {
        fail<InvalidArgument>("positions must hold 3 doubles per atom (", n, " atoms, got ",
                              positions.size(), " doubles)");
    }
    if (payload.size() != payload_width * n) {
        fail<InvalidArgument>("payload must hold payload_width = ", payload_width,
                              " doubles per atom (", n, " atoms, got ", payload.size(), ")");
    }
    for (std::size_t a = 0; a < n; ++a) {
        for (int k = 0; k < 3; ++k) {
            if (!std::isfinite(positions[3 * a + std::size_t(k)])) {
                fail<InvalidArgument>("position of atom id ", ids[a], " is not finite (got ",
                                      positions[3 * a + std::size_t(k)], ")");
            }
        }
    }
}

namespace {

// The owner of each atom; throws for a position too far away to wrap.
std::vector<int> owners(const Decomposition& decomposition, const Box& box,
                        const LocalAtoms& atoms) {
    std::vector<int> out(atoms.size());
    for (std::size_t a = 0; a < atoms.size(); ++a) {
        const Cartesian x(atoms.positions[3 * a], atoms.positions[3 * a + 1],
                          atoms.positions[3 * a + 2]);
        out[a] = decomposition.owner(box.wrap(box.to_fractional(x)).wrapped);
    }
    return out;
}

} // namespace

bool all_owned(const Decomposition& decomposition, const Box& box, const LocalAtoms& atoms) {
    std::vector<int> own;
    detail::agreed(decomposition.comm(), [&] {
        atoms.validate();
        own = owners(decomposition, box, atoms);
    });
    int mine = 1;
    for (int r : own) {
        mine &= int(r == decomposition.rank());
    }
    int all = 0;
    detail::check_mpi(MPI_Allreduce(&mine, &all, 1, MPI_INT, MPI_MIN, decomposition.comm()),
                      "MPI_Allreduce");
    return all == 1;
}

void migrate(const Decomposition& decomposition, const Box& box, LocalAtoms& atoms) {
    const MPI_Comm comm = decomposition.comm();
    const int size = decomposition.size();
    std::vector<int> own;
    detail::agreed(comm, [&] {
        atoms.validate();
        own = owners(decomposition, box, atoms);
    });
    unsigned long width[2] = {atoms.payload_width,
                              ~static_cast<unsigned long>(atoms.payload_width)};
    detail::check_mpi(MPI_Allreduce(MPI_IN_PLACE, width, 2, MPI_UNSIGNED_LONG, MPI_MAX, comm),
                      "MPI_Allreduce");
    detail::agree(comm, width[0] == ~width[1]
                            ? std::string()
                            : tricell::detail::cat("payload_width differs between ranks (",
                                                   atoms.payload_width, " here)"));

    // A record is the id, the position and the payload, as doubles (the id's bits copied).
    // MPI counts are ints: refuse, on every rank, what would not fit one.
    const std::size_t record = 4 + atoms.payload_width;
    detail::agree(comm, record * atoms.size() <= std::size_t(std::numeric_limits<int>::max())
                            ? std::string()
                            : tricell::detail::cat("migrate: ", atoms.size(), " atoms of ", record,
                                                   " doubles exceed one MPI message"));
    std::vector<int> send_counts(std::size_t(size), 0), send_offsets(std::size_t(size), 0);
    for (int r : own) {
        send_counts[std::size_t(r)] += int(record);
    }
    std::partial_sum(send_counts.begin(), send_counts.end() - 1, send_offsets.begin() + 1);
    std::vector<double> send(record * atoms.size());
    std::vector<int> cursor = send_offsets;
    for (std::size_t a = 0; a < atoms.size(); ++a) {
        double* out = send.data() + cursor[std::size_t(own[a])];
        cursor[std::size_t(own[a])] += int(record);
        std::memcpy(out, &atoms.ids[a], sizeof(double));
        std::memcpy(out + 1, &atoms.positions[3 * a], 3 * sizeof(double));
        if (record > 4) {
            std::memcpy(out + 4, &atoms.payload[atoms.payload_width * a],
                        atoms.payload_width * sizeof(double));
        }
    }
    std::vector<int> receive_counts(std::size_t(size), 0), receive_offsets(std::size_t(size), 0);
    detail::check_mpi(
        MPI_Alltoall(send_counts.data(), 1, MPI_INT, receive_counts.data(), 1, MPI_INT, comm),
        "MPI_Alltoall");
    std::size_t incoming = 0;
    for (int c : receive_counts) {
        incoming += std::size_t(c);
    }
    detail::agree(comm, incoming <= std::size_t(std::numeric_limits<int>::max())
                            ? std::string()
                            : tricell::detail::cat("migrate: ", incoming / record,
                                                   " incoming atoms exceed one MPI message"));
    std::partial_sum(receive_counts.begin(), receive_counts.end() - 1, receive_offsets.begin() + 1);
    const std::size_t total = std::size_t(receive_offsets.back() + receive_counts.back());
    std::vector<double> receive(total);
    detail::check_mpi(MPI_Alltoallv(send.data(), send_counts.data(), send_offsets.data(),
                                    MPI_DOUBLE, receive.data(), receive_counts.data(),
                                    receive_offsets.data(), MPI_DOUBLE, comm),
                      "MPI_Alltoallv");

    const std::size_t n = total / record;
    atoms.ids.resize(n);
    atoms.positions.resize(3 * n);
    atoms.payload.resize(atoms.payload_width * n);
    for (std::size_t a = 0; a < n; ++a) {
        const double* in = receive.data() + record * a;
        std::memcpy(&atoms.ids[a], in, sizeof(double));
        std::memcpy(&atoms.positions[3 * a], in + 1, 3 * sizeof(double));
        if (record > 4) {
            std::memcpy(&atoms.payload[atoms.payload_width * a], in + 4,
                        atoms.payload_width * sizeof(double));
        }
    }
}

namespace {

constexpr int tag_migrate = 7201;

// One atom as a record of doubles: the id's bits, the position, the payload.
void pack(const LocalAtoms& atoms, std::size_t a, std::vector<double>& out) {
    const std::size_t at = out.size();
    out.resize(at + 4 + atoms.payload_width);
    std::memcpy(&out[at], &atoms.ids[a], sizeof(double));
    std::memcpy(&out[at + 1], &atoms.positions[3 * a], 3 * sizeof(double));
    if (atoms.payload_width > 0) {
        std::memcpy(&out[at + 4], &atoms.payload[atoms.payload_width * a],
                    atoms.payload_width * sizeof(double));
    }
}

} // namespace

bool migrate(const Decomposition& decomposition, const Box& box, LocalAtoms& atoms,
             const std::vector<int>& neighbors, Traffic* sent) {
    const MPI_Comm comm = decomposition.comm();
    const int me = decomposition.rank();
    std::vector<int> own;
    int near = 1;
    try {
        atoms.validate();
        own = owners(decomposition, box, atoms);
        const std::size_t record = 4 + atoms.payload_width;
        near = int(record * atoms.size() <= std::size_t(std::numeric_limits<int>::max()));
        for (int r : own) {
            near &= int(r == me || std::binary_search(neighbors.begin(), neighbors.end(), r));
        }
    } catch (const std::exception&) {
        near = 0; // migrate() reports it on every rank
    }
    // The vote also covers the payload width: a width that differs goes to migrate() too.
    long vote[3] = {near, long(atoms.payload_width), -long(atoms.payload_width)};
    detail::check_mpi(MPI_Allreduce(MPI_IN_PLACE, vote, 3, MPI_LONG, MPI_MIN, comm),
                      "MPI_Allreduce");
    if (vote[0] == 0 || vote[1] != -vote[2]) {
        migrate(decomposition, box, atoms);
        return false;
    }
    // The sources in rank order (this rank among them), as MPI_Alltoallv would deliver them.
    std::vector<int> sources = neighbors;
    sources.insert(std::upper_bound(sources.begin(), sources.end(), me), me);
    std::vector<std::vector<double>> out(sources.size()), in(sources.size());
    for (std::size_t a = 0; a < atoms.size(); ++a) {
        const auto slot =
            std::size_t(std::lower_bound(sources.begin(), sources.end(), own[a]) - sources.begin());
        pack(atoms, a, out[slot]);
    }
    std::vector<MPI_Request> requests;
    requests.reserve(sources.size());
    std::uint64_t bytes_sent = 0;
    for (std::size_t n = 0; n < sources.size(); ++n) {
        if (sources[n] == me) {
            in[n].swap(out[n]);
            continue;
        }
        bytes_sent += out[n].size() * sizeof(double);
        requests.emplace_back();
        detail::check_mpi(MPI_Isend(out[n].data(), int(out[n].size()), MPI_DOUBLE, sources[n],
                                    tag_migrate, comm, &requests.back()),
                          "MPI_Isend");
    }
    for (std::size_t n = 0; n < sources.size(); ++n) {
        if (sources[n] == me) {
            continue;
        }
        MPI_Status status;
        detail::check_mpi(MPI_Probe(sources[n], tag_migrate, comm, &status), "MPI_Probe");
        int count = 0;
        MPI_Get_count(&status, MPI_DOUBLE, &count);
        in[n].resize(std::size_t(count));
        detail::check_mpi(MPI_Recv(in[n].data(), count, MPI_DOUBLE, sources[n], tag_migrate, comm,
                                   MPI_STATUS_IGNORE),
                          "MPI_Recv");
    }
    detail::check_mpi(MPI_Waitall(int(requests.size()), requests.data(), MPI_STATUSES_IGNORE),
                      "MPI_Waitall");
    if (sent) {
        sent->add(neighbors.size(), bytes_sent);
    }
    const std::size_t record = 4 + atoms.payload_width;
    std::size_t n = 0;
    for (const auto& v : in) {
        n += v.size() / record;
    }
    atoms.ids.resize(n);
    atoms.positions.resize(3 * n);
    atoms.payload.resize(atoms.payload_width * n);
    std::size_t a = 0;
    for (const auto& v : in) {
        for (std::size_t k = 0; k < v.size(); k += record, ++a) {
            std::memcpy(&atoms.ids[a], &v[k], sizeof(double));
            std::memcpy(&atoms.positions[3 * a], &v[k + 1], 3 * sizeof(double));
            if (atoms.payload_width > 0) {
                std::memcpy(&atoms.payload[atoms.payload_width * a], &v[k + 4],
                            atoms.payload_width * sizeof(double));
            }
        }
    }
    return true;
}

} // namespace tricell::mpi
