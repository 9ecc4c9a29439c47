// Halo: ghost selection per axis in fractional units, and the point-to-point exchange (halo.hpp).
#include "tricell/mpi/halo.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

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

// One candidate along one axis: the interval of the destination and the translation.
struct AxisHit {
    int interval;
    int t;
};

// The halo half-widths in fractional units, h = reach / w per axis, widened by a few ulps so that
// a pair at exactly the limit (after rounding of s) is never lost. Extra ghosts are harmless.
Eigen::Vector3d halo_widths(const Box& box, double reach) {
    Eigen::Vector3d h;
    for (int k = 0; k < 3; ++k) {
        h[k] = reach / box.perpendicular_widths()[k] * (1 + 1e-10) + 1e-12;
    }
    return h;
}

// Extent of interval k along an axis: end intervals of an open axis reach to infinity.
double interval_lo(const Decomposition& d, int axis, int k, bool periodic) {
    return (!periodic && k == 0) ? -std::numeric_limits<double>::infinity()
                                 : d.bounds(axis)[std::size_t(k)];
}
double interval_hi(const Decomposition& d, int axis, int k, bool periodic) {
    return (!periodic && k == d.dims()[std::size_t(axis)] - 1)
               ? std::numeric_limits<double>::infinity()
               : d.bounds(axis)[std::size_t(k) + 1];
}

// The (interval, translation) pairs whose halo contains s + t along one axis.
void axis_hits(const Decomposition& d, int axis, bool periodic, double s, double h,
               std::vector<AxisHit>& out) {
    out.clear();
    const int n = d.dims()[std::size_t(axis)];
    const int t_lo = periodic ? int(std::ceil(-h - s)) - 1 : 0;
    const int t_hi = periodic ? int(std::floor(1 + h - s)) + 1 : 0;
    for (int t = t_lo; t <= t_hi; ++t) {
        const double v = s + t;
        for (int k = 0; k < n; ++k) {
            if (v >= interval_lo(d, axis, k, periodic) - h &&
                v <= interval_hi(d, axis, k, periodic) + h) {
                out.push_back({k, t});
            }
        }
    }
}

// The intervals along an axis whose halo some translate of interval `mine` reaches (a symmetric
// relation between intervals, hence between domains).
std::vector<int> axis_neighbors(const Decomposition& d, int axis, bool periodic, int mine,
                                double h) {
    std::vector<int> out;
    const double lo = interval_lo(d, axis, mine, periodic);
    const double hi = interval_hi(d, axis, mine, periodic);
    for (int k = 0; k < d.dims()[std::size_t(axis)]; ++k) {
        const double klo = interval_lo(d, axis, k, periodic) - h;
        const double khi = interval_hi(d, axis, k, periodic) + h;
        const bool hit =
            periodic ? std::ceil(klo - hi) <= std::floor(khi - lo) : (klo <= hi && lo <= khi);
        if (hit) {
            out.push_back(k);
        }
    }
    return out;
}

// Whether a ghost sent from grid position `from` through translation t is upper at grid position
// `to` (halo.hpp, "Upper halos"): from + t * dims - to lexicographically positive.
bool upper(const std::array<int, 3>& t, const std::array<int, 3>& from,
           const std::array<int, 3>& to, const std::array<int, 3>& dims) {
    for (std::size_t k = 0; k < 3; ++k) {
        const int offset = from[k] + t[k] * dims[k] - to[k];
        if (offset != 0) {
            return offset > 0;
        }
    }
    return false;
}

} // namespace

void Halo::build(const Decomposition& decomposition, const Box& box,
                 const std::vector<std::uint64_t>& ids, PointsView positions, double reach,
                 const std::vector<double>* radii, const std::vector<std::int32_t>* species,
                 GhostSet ghosts) {
    const int me = decomposition.rank();
    std::vector<Fractional> wrapped(positions.size());
    std::vector<Shift> image(positions.size());
    detail::agreed(decomposition.comm(), [&] {
        if (!(std::isfinite(reach) && reach > 0)) {
            fail<InvalidArgument>("halo reach must be > 0 (got ", reach, ")");
        }
        if (positions.size() != ids.size()) {
            fail<InvalidArgument>("halo needs one id per position (", ids.size(), " ids, ",
                                  positions.size(), " positions)");
        }
        if (radii && radii->size() != ids.size()) {
            fail<InvalidArgument>("radii must hold one value per owned atom (", ids.size(),
                                  " atoms, got ", radii->size(), ")");
        }
        if (species && species->size() != ids.size()) {
            fail<InvalidArgument>("species must hold one value per owned atom (", ids.size(),
                                  " atoms, got ", species->size(), ")");
        }
        for (std::size_t a = 0; a < positions.size(); ++a) {
            const Eigen::Vector3d x = positions[a];
            if (!x.allFinite()) {
                fail<InvalidArgument>("position of atom id ", ids[a], " is not finite");
            }
            const WrappedFractional w = box.wrap(box.to_fractional(Cartesian(x)));
            const int owner = decomposition.owner(w.wrapped);
            if (owner != me) {
                fail<InvalidArgument>("atom id ", ids[a], " at fractional (", w.wrapped[0], ", ",
                                      w.wrapped[1], ", ", w.wrapped[2], ") belongs to rank ", owner,
                                      ", not ", me, "; call tricell::mpi::migrate() first");
            }
            wrapped[a] = w.wrapped;
            image[a] = w.image;
        }
    });

    reach_ = reach;
    ghost_set_ = ghosts;
    pbc_ = box.periodicity();
    owned_ = positions.size();
    const Eigen::Vector3d h = halo_widths(box, reach);

    // The neighbour ranks: products of the per-axis neighbour intervals, without this rank.
    const std::array<int, 3> my = decomposition.coords(me);
    std::array<std::vector<int>, 3> near;
    for (int k = 0; k < 3; ++k) {
        near[std::size_t(k)] = axis_neighbors(decomposition, k, pbc_[k], my[std::size_t(k)], h[k]);
    }
    neighbors_.clear();
    for (int a : near[0]) {
        for (int b : near[1]) {
            for (int c : near[2]) {
                const int r = decomposition.rank_at({{a, b, c}});
                if (r != me) {
                    neighbors_.push_back(r);
                }
            }
        }
    }
    std::sort(neighbors_.begin(), neighbors_.end());
    std::vector<int> slot(std::size_t(decomposition.size()), -1);
    for (std::size_t n = 0; n < neighbors_.size(); ++n) {
        slot[std::size_t(neighbors_[n])] = int(n);
    }

    // Owned atoms in the local frame, and their ghosts' destinations.
    y_.resize(3 * owned_);
    images_.resize(3 * owned_);
    ids_.assign(ids.begin(), ids.end());
    with_radii_ = radii != nullptr;
    with_species_ = species != nullptr;
    radii_ = with_radii_ ? *radii : std::vector<double>();
    species_ = with_species_ ? *species : std::vector<std::int32_t>();
    reference_.resize(3 * owned_);
    sends_.assign(neighbors_.size(), {});
    self_sends_.clear();
    std::array<std::vector<AxisHit>, 3> hits;
    const std::array<int, 3>& dims = decomposition.dims();
    const bool upper_only = ghosts == GhostSet::upper;
    for (std::size_t a = 0; a < owned_; ++a) {
        const Cartesian y = box.to_cartesian(wrapped[a]);
        for (int k = 0; k < 3; ++k) {
            y_[3 * a + std::size_t(k)] = y[k];
            images_[3 * a + std::size_t(k)] = image[a][k];
            reference_[3 * a + std::size_t(k)] = wrapped[a][k];
            axis_hits(decomposition, k, pbc_[k], wrapped[a][k], h[k], hits[std::size_t(k)]);
        }
        for (const AxisHit& ha : hits[0]) {
            for (const AxisHit& hb : hits[1]) {
                for (const AxisHit& hc : hits[2]) {
                    const std::array<int, 3> to{{ha.interval, hb.interval, hc.interval}};
                    if (upper_only && !upper({{ha.t, hb.t, hc.t}}, my, to, dims)) {
                        continue;
                    }
                    const int r = decomposition.rank_at(to);
                    const Send send{std::uint32_t(a), {ha.t, hb.t, hc.t}};
                    if (r == me) {
                        if (ha.t != 0 || hb.t != 0 || hc.t != 0) {
                            self_sends_.push_back(send);
                        }
                    } else if (slot[std::size_t(r)] >= 0) {
                        sends_[std::size_t(slot[std::size_t(r)])].push_back(send);
                    } else {
                        fail<Error>("internal: rank ", r, " is not a halo neighbour of ", me);
                    }
                }
            }
        }
    }
    exchange(decomposition, box);
}

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
