// Ghost atoms: copies of the atoms within a reach of a rank's domain, with their image shifts.
//
// Selection is in fractional space. A point within Cartesian distance r of a point of the domain
// differs from it by less than r / w_alpha in fractional coordinate alpha (w_alpha the
// perpendicular width of the box), so the halo of a domain [lo, hi) is the fractional box
// [lo - h, hi + h] with h_alpha = r / w_alpha per axis (a superset of the Cartesian shell; extra
// ghosts are harmless). Every owner enumerates, for each of its atoms (wrapped position s), every
// pair (destination domain, lattice translation T) with s + T inside the destination's halo, T
// running over all translations along periodic axes that reach it: when r exceeds a domain's
// width the halo is several domains deep, and when it exceeds the box a domain receives images of
// its own atoms (T != 0; the atom itself with T = 0 is never its own ghost). Each (atom, T) is
// sent at most once to a rank, so ghosts are unique.
//
// Local frame. Every local atom a (owned first, then ghosts) has a position y_a in one
// continuous frame and an integer image c_a with y_a = x_{id(a)} - H c_a, x the owner's caller
// position. An owned atom has y = its wrapped position (c = its wrap image); a ghost of it sent
// with translation T has y = y_owner + H T and c = c_owner - T. A local pair a -> b then has
// D = y_b - y_a = x_j - x_i + H (c_a - c_b): the global pair (id(a), id(b), S = c_a - c_b), S
// relative to the caller's positions.
//
// Upper halos (Newton's third law). A ghost comes from an owner rank B through a translation T;
// place it in the domain grid continued periodically, at G = g(B) + T * dims (g a rank's grid
// coordinates, * per axis), and call it upper on rank A when G - g(A) is lexicographically
// positive (first axis first). An owned-ghost pair (a on A, the image of b on B through T) is,
// on B, the pair (b, the image of a through -T), whose offset is the negation; the offset is zero
// only for T = 0 and A = B, an owned-owned pair. Both ends lie in their domains at a build and
// within the reach of each other, so each end's image is in the other's halo: with upper halos
// (GhostSet::upper) every owned-ghost pair within the reach is found on exactly one rank, the
// one where its ghost is upper, and no rule on coordinates (which rounding would make differ
// between the two ranks) is needed. It is LAMMPS's half stencil of "newton on" at the level of
// domains; on a grid of equal domains every rank holds half the ghosts of the full halo (the
// upper half of its neighbourhood), and one rank alone keeps its images through T > 0. The
// neighbour ranks, and so the messages, are those of the full halo (some messages are empty).
//
// Per-atom attributes. A build may carry a radius and a species per owned atom (for the
// variable cutoffs of NeighborOptions); every ghost has its owner's, in radii() and species().
//
// Communication. The ranks exchanging ghosts are those whose domains come within h of each other
// through some T, a symmetric relation both sides compute from the boundaries alone; each pair
// of neighbour ranks exchanges exactly one message per exchange (empty or not), point to point
// (MPI_Isend, then MPI_Probe / MPI_Get_count / MPI_Recv). update() re-sends the same ghosts with
// fresh positions and images only (the Verlet steps between rebuilds), into the same slots;
// images of a rank's own atoms are written in place, not sent.
//
// Forward and reverse communication of per-atom values (LAMMPS's forward_comm / reverse_comm).
// forward() copies `width` doubles per owned atom into every ghost of it (charges, densities,
// velocities); reverse_sum() adds the `width` doubles of every ghost slot into its owner's row
// (the forces and virial contributions a force loop over a Newton half list put on ghosts). Both
// use the halo's own neighbour relation and slots: one message each way per neighbour rank,
// images of a rank's own atoms handled locally, in a fixed order (so the sums are the same on
// every run).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "tricell/box.hpp"
#include "tricell/mpi/decomposition.hpp"
#include "tricell/mpi/export.hpp"
#include "tricell/types.hpp"

namespace tricell::mpi {

/// What one exchange cost on this rank.
struct HaloStats {
    std::size_t owned = 0;
    std::size_t ghosts = 0;
    int neighbor_ranks = 0; ///< other ranks this rank exchanges with (one message each way)
    std::size_t bytes_sent = 0;
    int messages_sent = 0; ///< messages this rank sent in the exchange (one per neighbour rank)
};

/// Which ghosts a halo gathers: every image within the reach of the domain (full lists, and any
/// use of ghosts besides pairs), or the upper ones only (half lists with Newton's third law; see
/// "Upper halos" above).
enum class GhostSet { all, upper };

class TRICELL_MPI_API Halo {
  public:
    /// Bytes per ghost on the wire: a build sends id, position, image, species and radius; an
    /// update() sends the position and image.
    static constexpr std::size_t build_record_bytes = 56;
    static constexpr std::size_t update_record_bytes = 40;

    /// Collective. Selects and exchanges the ghosts within `reach` (Cartesian, > 0) of each
    /// domain. radii / species, when not null (on every rank alike), hold one value per owned
    /// atom and travel with the ghosts. positions are the owned atoms' caller positions; every atom
    /// must lie in this rank's domain (after migrate()), else InvalidArgument on every rank.
    /// `ghosts` (the same on every rank): all of them, or the upper ones only.
    void build(const Decomposition& decomposition, const Box& box,
               const std::vector<std::uint64_t>& ids, PointsView positions, double reach,
               const std::vector<double>* radii = nullptr,
               const std::vector<std::int32_t>* species = nullptr, GhostSet ghosts = GhostSet::all);
    /// Collective. New caller positions of the same owned atoms (same order), possibly in a new
    /// box of the same periodicity: re-sends the ghosts of the build with fresh positions. Each
    /// atom's image c follows its caller position across wrapping (the rounded fractional jump
    /// since the build), so y stays continuous.
    void update(const Decomposition& decomposition, const Box& box, PointsView positions);

    /// Collective. values holds `width` doubles per local atom (size() rows, owned first): each
    /// ghost row becomes a copy of its owner's row. InvalidArgument on every rank when a size
    /// differs.
    void forward(const Decomposition& decomposition, std::vector<double>& values,
                 std::size_t width) const;
    /// Collective. values holds `width` doubles per local atom (size() rows, owned first): each
    /// ghost row is added into its owner's row (on this rank or another); ghost rows are left as
    /// they were. InvalidArgument on every rank when a size differs.
    void reverse_sum(const Decomposition& decomposition, std::vector<double>& values,
                     std::size_t width) const;
    /// Bytes and messages this rank sent in its last forward() or reverse_sum().
    std::size_t comm_bytes_sent() const { return comm_bytes_; }
    int comm_messages_sent() const { return comm_messages_; }

    std::size_t owned_count() const { return owned_; }
    std::size_t ghost_count() const { return ids_.size() - owned_; }
    std::size_t size() const { return ids_.size(); }
    double reach() const { return reach_; }
    GhostSet ghost_set() const { return ghost_set_; }
    /// y per local atom (owned first, then ghosts), 3 doubles each.
    const std::vector<double>& positions() const { return y_; }
    PointsView points() const { return PointsView(y_.data(), ids_.size()); }
    /// Global id per local atom.
    const std::vector<std::uint64_t>& ids() const { return ids_; }
    /// c per local atom, 3 ints each: y = x_caller - H c.
    const std::vector<std::int32_t>& images() const { return images_; }
    Shift image(std::size_t a) const {
        return Shift(images_[3 * a], images_[3 * a + 1], images_[3 * a + 2]);
    }
    /// Radius and species per local atom (empty unless the build was given them).
    const std::vector<double>& radii() const { return radii_; }
    const std::vector<std::int32_t>& species() const { return species_; }
    /// The other ranks this rank exchanges ghosts with (ascending).
    const std::vector<int>& neighbor_ranks() const { return neighbors_; }
    const HaloStats& stats() const { return stats_; }

  private:
    // build() and the selection are lib/mpi/halo_selection.cpp, every exchange (update(),
    // forward(), reverse_sum()) lib/mpi/halo_exchange.cpp.
    // One ghost to send: owned atom index and translation.
    struct Send {
        std::uint32_t atom;
        std::int32_t t[3];
    };
    // update() is the collective check, then place_owned() and send_positions(); the
    // distributed Verlet list takes its own check and rebuild vote in one MPI_Allreduce, so it
    // calls the two parts itself.
    friend class DistributedVerletList;
    // y and c of the owned atoms from their new caller positions (checked already; no MPI).
    void place_owned(const Box& box, PointsView positions);
    // The build's exchange of ghost records (and their slots), and update()'s of positions.
    void exchange(const Decomposition& decomposition, const Box& box);
    void send_positions(const Decomposition& decomposition, const Box& box);
    // The first local slot of the ghosts received from neighbour n.
    std::size_t first_slot(std::size_t n) const;
    void check_values(const Decomposition& decomposition, const std::vector<double>& values,
                      std::size_t width, const char* what) const;

    double reach_ = 0;
    GhostSet ghost_set_ = GhostSet::all;
    std::size_t owned_ = 0;
    Periodicity pbc_;
    std::vector<double> y_;
    std::vector<std::uint64_t> ids_;
    std::vector<std::int32_t> images_;
    std::vector<double> radii_;
    std::vector<std::int32_t> species_;
    bool with_radii_ = false, with_species_ = false;
    // Fractional y of the owned atoms at the build, to follow their wrapping afterwards.
    std::vector<double> reference_;
    std::vector<int> neighbors_;
    // Per neighbour rank (same order as neighbors_): the ghosts to send; ghosts to this rank's
    // own domain (T != 0) are in self_sends_.
    std::vector<std::vector<Send>> sends_;
    std::vector<Send> self_sends_;
    // Per neighbour rank: how many ghosts it sent at the build (the slots of update()).
    std::vector<std::size_t> received_;
    HaloStats stats_;
    mutable std::size_t comm_bytes_ = 0;
    mutable int comm_messages_ = 0;
};

} // namespace tricell::mpi
