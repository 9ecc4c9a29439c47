// The halo's exchanges, by the rules of tricell/mpi/halo.hpp ("Communication", "Forward and
// reverse communication"): the build's ghost records (received with MPI_Probe, since a rank
// does not know how many it gets), update()'s new positions and images, and forward() and
// reverse_sum() of per-atom values, all between the neighbour ranks the selection found
// (halo_selection.cpp). Ghost slots keep one order, the images of the rank's own atoms first,
// then each neighbour's ghosts in rank order, so every later exchange finds a ghost where the
// build put it and the reverse sums add in a fixed order.
#include "tricell/mpi/halo.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "collective.hpp"
#include "tricell/error.hpp"

namespace tricell::mpi {

using tricell::detail::fail;

namespace {

constexpr int tag_build = 7101;
constexpr int tag_update = 7102;
constexpr int tag_forward = 7103;
constexpr int tag_reverse = 7104;

// What travels per ghost.
struct Record {
    std::uint64_t id;
    double y[3];
    std::int32_t c[3];
    std::int32_t species;
    double radius;
};

// What travels per ghost in update(): the new position and image (the rest is the build's).
struct Moved {
    double y[3];
    std::int32_t c[3];
    std::int32_t unused; // zero: no uninitialised bytes on the wire
};

static_assert(sizeof(Record) == Halo::build_record_bytes, "the build's record is 56 bytes");
static_assert(sizeof(Moved) == Halo::update_record_bytes, "the update's record is 40 bytes");

} // namespace

void Halo::update(const Decomposition& decomposition, const Box& box, PointsView positions) {
    detail::agreed(decomposition.comm(), [&] {
        if (positions.size() != owned_) {
            fail<InvalidArgument>("halo update needs the ", owned_,
                                  " owned atoms of the build (got ", positions.size(), ")");
        }
        if (box.periodicity() != pbc_) {
            fail<InvalidArgument>("halo update needs the periodicity of the build");
        }
        for (std::size_t a = 0; a < owned_; ++a) {
            if (!Eigen::Vector3d(positions[a]).allFinite()) {
                fail<InvalidArgument>("position of atom id ", ids_[a], " is not finite");
            }
        }
    });
    place_owned(box, positions);
    send_positions(decomposition, box);
}

void Halo::place_owned(const Box& box, PointsView positions) {
    const Eigen::Matrix3d& hm = box.matrix();
    for (std::size_t a = 0; a < owned_; ++a) {
        const Eigen::Vector3d x = positions[a];
        const Eigen::Vector3d s = box.inverse() * x;
        Eigen::Vector3d c = Eigen::Vector3d::Zero();
        for (int k = 0; k < 3; ++k) {
            if (pbc_[k]) {
                c[k] = std::nearbyint(s[k] - reference_[3 * a + std::size_t(k)]);
            }
        }
        const Eigen::Vector3d y = x - hm * c;
        for (int k = 0; k < 3; ++k) {
            y_[3 * a + std::size_t(k)] = y[k];
            images_[3 * a + std::size_t(k)] = std::int32_t(c[k]);
        }
    }
}

void Halo::send_positions(const Decomposition& decomposition, const Box& box) {
    const MPI_Comm comm = decomposition.comm();
    const Eigen::Matrix3d& hm = box.matrix();
    // Ghost g of owned atom a with translation T: y_g = y_a + H T, c_g = c_a - T.
    auto moved = [&](const Send& send, double* y, std::int32_t* c) {
        const std::size_t a = send.atom;
        const double t0 = send.t[0], t1 = send.t[1], t2 = send.t[2];
        for (int k = 0; k < 3; ++k) {
            y[k] = y_[3 * a + std::size_t(k)] + (hm(k, 0) * t0 + hm(k, 1) * t1 + hm(k, 2) * t2);
            c[k] = images_[3 * a + std::size_t(k)] - send.t[k];
        }
    };
    std::vector<std::vector<Moved>> out(neighbors_.size()), in(neighbors_.size());
    std::vector<MPI_Request> requests;
    requests.reserve(2 * neighbors_.size());
    stats_.bytes_sent = 0;
    stats_.messages_sent = int(neighbors_.size());
    for (std::size_t n = 0; n < neighbors_.size(); ++n) {
        in[n].resize(received_[n]);
        requests.emplace_back();
        detail::check_mpi(MPI_Irecv(in[n].data(), int(received_[n] * sizeof(Moved)), MPI_BYTE,
                                    neighbors_[n], tag_update, comm, &requests.back()),
                          "MPI_Irecv");
    }
    for (std::size_t n = 0; n < neighbors_.size(); ++n) {
        out[n].resize(sends_[n].size());
        for (std::size_t g = 0; g < sends_[n].size(); ++g) {
            Moved& m = out[n][g];
            moved(sends_[n][g], m.y, m.c);
            m.unused = 0;
        }
        const std::size_t bytes = out[n].size() * sizeof(Moved);
        stats_.bytes_sent += bytes;
        requests.emplace_back();
        detail::check_mpi(MPI_Isend(out[n].data(), int(bytes), MPI_BYTE, neighbors_[n], tag_update,
                                    comm, &requests.back()),
                          "MPI_Isend");
    }
    // Images of this rank's own atoms straight into their slots, then each neighbour's.
    for (std::size_t g = 0; g < self_sends_.size(); ++g) {
        const std::size_t slot = owned_ + g;
        moved(self_sends_[g], &y_[3 * slot], &images_[3 * slot]);
    }
    detail::check_mpi(MPI_Waitall(int(requests.size()), requests.data(), MPI_STATUSES_IGNORE),
                      "MPI_Waitall");
    for (std::size_t n = 0; n < neighbors_.size(); ++n) {
        std::size_t slot = first_slot(n);
        for (const Moved& m : in[n]) {
            for (int k = 0; k < 3; ++k) {
                y_[3 * slot + std::size_t(k)] = m.y[k];
                images_[3 * slot + std::size_t(k)] = m.c[k];
            }
            ++slot;
        }
    }
}

void Halo::exchange(const Decomposition& decomposition, const Box& box) {
    const MPI_Comm comm = decomposition.comm();
    const Eigen::Matrix3d& hm = box.matrix();
    auto fill = [&](const Send& send, Record& r) {
        const std::size_t a = send.atom;
        const Eigen::Vector3d t(send.t[0], send.t[1], send.t[2]);
        const Eigen::Vector3d y = Eigen::Vector3d(y_[3 * a], y_[3 * a + 1], y_[3 * a + 2]) + hm * t;
        r.id = ids_[a];
        r.species = with_species_ ? species_[a] : 0;
        r.radius = with_radii_ ? radii_[a] : 0;
        for (int k = 0; k < 3; ++k) {
            r.y[k] = y[k];
            r.c[k] = images_[3 * a + std::size_t(k)] - send.t[k];
        }
    };

    // Pack and post every send (one message per neighbour, empty or not).
    std::vector<std::vector<Record>> out(neighbors_.size());
    std::vector<MPI_Request> requests;
    requests.reserve(2 * neighbors_.size());
    const int tag = tag_build;
    stats_.bytes_sent = 0;
    stats_.messages_sent = int(neighbors_.size());
    for (std::size_t n = 0; n < neighbors_.size(); ++n) {
        out[n].resize(sends_[n].size());
        for (std::size_t g = 0; g < sends_[n].size(); ++g) {
            fill(sends_[n][g], out[n][g]);
        }
        const std::size_t bytes = out[n].size() * sizeof(Record);
        stats_.bytes_sent += bytes;
        requests.emplace_back();
        detail::check_mpi(MPI_Isend(out[n].data(), int(bytes), MPI_BYTE, neighbors_[n], tag, comm,
                                    &requests.back()),
                          "MPI_Isend");
    }

    // Ghosts: images of this rank's own atoms first, then each neighbour's in rank order.
    std::vector<Record> self(self_sends_.size());
    for (std::size_t g = 0; g < self_sends_.size(); ++g) {
        fill(self_sends_[g], self[g]);
    }
    std::vector<std::vector<Record>> in(neighbors_.size());
    received_.assign(neighbors_.size(), 0);
    for (std::size_t n = 0; n < neighbors_.size(); ++n) {
        MPI_Status status;
        detail::check_mpi(MPI_Probe(neighbors_[n], tag, comm, &status), "MPI_Probe");
        int bytes = 0;
        MPI_Get_count(&status, MPI_BYTE, &bytes);
        in[n].resize(std::size_t(bytes) / sizeof(Record));
        received_[n] = in[n].size();
        detail::check_mpi(
            MPI_Recv(in[n].data(), bytes, MPI_BYTE, neighbors_[n], tag, comm, MPI_STATUS_IGNORE),
            "MPI_Recv");
    }
    detail::check_mpi(MPI_Waitall(int(requests.size()), requests.data(), MPI_STATUSES_IGNORE),
                      "MPI_Waitall");

    std::size_t ghosts = self.size();
    for (const auto& v : in) {
        ghosts += v.size();
    }
    const std::size_t total = owned_ + ghosts;
    y_.resize(3 * total);
    images_.resize(3 * total);
    ids_.resize(total);
    radii_.resize(with_radii_ ? total : 0);
    species_.resize(with_species_ ? total : 0);
    std::size_t a = owned_;
    auto store = [&](const Record& r) {
        ids_[a] = r.id;
        if (with_radii_) {
            radii_[a] = r.radius;
        }
        if (with_species_) {
            species_[a] = r.species;
        }
        for (int k = 0; k < 3; ++k) {
            y_[3 * a + std::size_t(k)] = r.y[k];
            images_[3 * a + std::size_t(k)] = r.c[k];
        }
        ++a;
    };
    for (const Record& r : self) {
        store(r);
    }
    for (const auto& v : in) {
        for (const Record& r : v) {
            store(r);
        }
    }
    stats_.owned = owned_;
    stats_.ghosts = ghosts;
    stats_.neighbor_ranks = int(neighbors_.size());
}

std::size_t Halo::first_slot(std::size_t n) const {
    std::size_t slot = owned_ + self_sends_.size();
    for (std::size_t m = 0; m < n; ++m) {
        slot += received_[m];
    }
    return slot;
}

void Halo::check_values(const Decomposition& decomposition, const std::vector<double>& values,
                        std::size_t width, const char* what) const {
    detail::agreed(decomposition.comm(), [&] {
        if (values.size() != width * ids_.size()) {
            fail<InvalidArgument>(what, " needs ", width, " values per local atom (", ids_.size(),
                                  " atoms: ", width * ids_.size(), " values), got ", values.size());
        }
    });
}

void Halo::forward(const Decomposition& decomposition, std::vector<double>& values,
                   std::size_t width) const {
    check_values(decomposition, values, width, "Halo::forward");
    const MPI_Comm comm = decomposition.comm();
    std::vector<std::vector<double>> out(neighbors_.size());
    std::vector<MPI_Request> requests;
    requests.reserve(2 * neighbors_.size());
    comm_bytes_ = 0;
    comm_messages_ = int(neighbors_.size());
    for (std::size_t n = 0; n < neighbors_.size(); ++n) {
        out[n].resize(width * sends_[n].size());
        for (std::size_t g = 0; g < sends_[n].size(); ++g) {
            std::copy_n(&values[width * sends_[n][g].atom], width, &out[n][width * g]);
        }
        comm_bytes_ += out[n].size() * sizeof(double);
        requests.emplace_back();
        detail::check_mpi(MPI_Isend(out[n].data(), int(out[n].size()), MPI_DOUBLE, neighbors_[n],
                                    tag_forward, comm, &requests.back()),
                          "MPI_Isend");
    }
    for (std::size_t g = 0; g < self_sends_.size(); ++g) {
        std::copy_n(&values[width * self_sends_[g].atom], width, &values[width * (owned_ + g)]);
    }
    for (std::size_t n = 0; n < neighbors_.size(); ++n) {
        requests.emplace_back();
        detail::check_mpi(MPI_Irecv(values.data() + width * first_slot(n),
                                    int(width * received_[n]), MPI_DOUBLE, neighbors_[n],
                                    tag_forward, comm, &requests.back()),
                          "MPI_Irecv");
    }
    detail::check_mpi(MPI_Waitall(int(requests.size()), requests.data(), MPI_STATUSES_IGNORE),
                      "MPI_Waitall");
}

void Halo::reverse_sum(const Decomposition& decomposition, std::vector<double>& values,
                       std::size_t width) const {
    check_values(decomposition, values, width, "Halo::reverse_sum");
    const MPI_Comm comm = decomposition.comm();
    std::vector<std::vector<double>> in(neighbors_.size());
    std::vector<MPI_Request> requests;
    requests.reserve(2 * neighbors_.size());
    comm_bytes_ = 0;
    comm_messages_ = int(neighbors_.size());
    // Each neighbour gets back the rows of the ghosts it sent, in the order it sent them.
    for (std::size_t n = 0; n < neighbors_.size(); ++n) {
        in[n].resize(width * sends_[n].size());
        requests.emplace_back();
        detail::check_mpi(MPI_Irecv(in[n].data(), int(in[n].size()), MPI_DOUBLE, neighbors_[n],
                                    tag_reverse, comm, &requests.back()),
                          "MPI_Irecv");
    }
    for (std::size_t n = 0; n < neighbors_.size(); ++n) {
        const std::size_t count = width * received_[n];
        comm_bytes_ += count * sizeof(double);
        requests.emplace_back();
        detail::check_mpi(MPI_Isend(values.data() + width * first_slot(n), int(count), MPI_DOUBLE,
                                    neighbors_[n], tag_reverse, comm, &requests.back()),
                          "MPI_Isend");
    }
    detail::check_mpi(MPI_Waitall(int(requests.size()), requests.data(), MPI_STATUSES_IGNORE),
                      "MPI_Waitall");
    // Sums in a fixed order: images of this rank's own atoms, then each neighbour's rows.
    auto add = [&](std::size_t atom, const double* row) {
        for (std::size_t c = 0; c < width; ++c) {
            values[width * atom + c] += row[c];
        }
    };
    for (std::size_t g = 0; g < self_sends_.size(); ++g) {
        add(self_sends_[g].atom, &values[width * (owned_ + g)]);
    }
    for (std::size_t n = 0; n < neighbors_.size(); ++n) {
        for (std::size_t g = 0; g < sends_[n].size(); ++g) {
            add(sends_[n][g].atom, &in[n][width * g]);
        }
    }
}

} // namespace tricell::mpi
