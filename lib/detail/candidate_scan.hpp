// The shared inner loop of every backend: a backend names candidate (atom range, atom range,
// image shift) triples in its own atom order, and the CandidateScanner tests them against the
// cutoff through the run-time selected distance kernel, turns each hit into the caller's indices
// and an image shift relative to the caller's positions, applies a variable cutoff when there is
// one, orients half-list pairs canonically and hands them to the PairSink.
//
// Positions live in an AtomTable: the wrapped Cartesian positions struct-of-arrays in the
// backend's order (contiguous ranges stream through the vectorised kernel), the integer image
// each came from (x = wrapped + H image) and the caller's index of each. A pair (a, b) found
// through the cell shift s has D = x_b + H s - x_a in the search frame and, for the caller,
// S = s + image_a - image_b.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "detail/pair_sink.hpp"
#include "tricell/detail/distance_kernel.hpp"
#include "tricell/neighbor_list.hpp"

namespace tricell::detail {

/// Positions in a backend's order (see above).
struct AtomTable {
    std::vector<double> x, y, z;
    std::vector<std::int32_t> image;  ///< 3 per atom
    std::vector<std::uint32_t> index; ///< the caller's index of each atom
    std::size_t size() const { return index.size(); }
};

/// Which pairs count when the cutoff varies: per-atom radii (d < r_i + r_j) or a per-species-pair
/// table (d < r(s_i, s_j); a missing species pair never counts). Uniform otherwise, where the
/// scan's threshold alone decides.
class CutoffRule {
  public:
    /// Validates radii / species against the atom count and builds the lookup tables.
    void set(const NeighborOptions& options, std::size_t atom_count);
    bool uniform() const { return kind_ == Kind::uniform; }
    /// The largest cutoff any pair can have (0: no pair can count).
    double max_cutoff() const { return max_cutoff_; }
    /// For a candidate already within max_cutoff(): does it count?
    bool accepts(std::uint32_t i, std::uint32_t j, double d_sq) const {
        if (kind_ == Kind::radii) {
            return std::sqrt(d_sq) < radii_[i] + radii_[j];
        }
        return d_sq < threshold_sq_[std::size_t(species_index_[i]) * kinds_ +
                                    std::size_t(species_index_[j])];
    }

  private:
    enum class Kind { uniform, radii, species };
    Kind kind_ = Kind::uniform;
    double max_cutoff_ = 0;
    std::vector<double> radii_;
    std::vector<std::uint32_t> species_index_; // dense index of each atom's species
    std::size_t kinds_ = 0;
    std::vector<double> threshold_sq_; // kinds_ x kinds_ strict thresholds (0: never)
};

/// An image shift s (search frame) and its Cartesian vector H s.
struct ImageShift {
    int s[3];
    double vx, vy, vz;
};

class CandidateScanner {
  public:
    CandidateScanner(const AtomTable& atoms, const Eigen::Matrix3d& h, double cutoff_sq,
                     const CutoffRule& rule, bool half, const Eigen::Matrix3i& to_caller,
                     bool reduced_frame, PairSink& sink)
        : x_(atoms.x.data()), y_(atoms.y.data()), z_(atoms.z.data()), image_(atoms.image.data()),
          index_(atoms.index.data()), h_(h), cutoff_sq_(cutoff_sq), rule_(rule), half_(half),
          to_caller_(to_caller), reduced_frame_(reduced_frame), sink_(sink) {}

    ImageShift shift(int sa, int sb, int sc) const {
        const Eigen::Vector3d v = h_.col(0) * sa + h_.col(1) * sb + h_.col(2) * sc;
        return ImageShift{{sa, sb, sc}, v.x(), v.y(), v.z()};
    }

    /// Every a in [a0, a1) with every b in [b0, b1) through `s`. With `own` the two ranges hold
    /// the same atoms through a zero shift (b0 <= a0, a1 <= b1): a full list skips b == a, a half
    /// list takes only b > a (then b0 == a0 is required, so each unordered pair is seen once).
    void ranges(std::uint32_t a0, std::uint32_t a1, std::uint32_t b0, std::uint32_t b1,
                const ImageShift& s, bool own) {
        tests_ += std::uint64_t(a1 - a0) * std::uint64_t(b1 - b0);
        for (std::uint32_t a = a0; a < a1; ++a) {
            const double ax = x_[a] - s.vx, ay = y_[a] - s.vy, az = z_[a] - s.vz;
            if (!own) {
                scan(a, b0, b1, ax, ay, az, s);
            } else if (half_) {
                scan(a, a + 1, b1, ax, ay, az, s);
            } else {
                scan(a, b0, a, ax, ay, az, s);
                scan(a, a + 1, b1, ax, ay, az, s);
            }
        }
    }

    /// One candidate pair (a, b) through `s` (backends without contiguous ranges).
    void pair(std::uint32_t a, std::uint32_t b, const ImageShift& s) {
        ++tests_;
        const double dx = x_[b] - (x_[a] - s.vx);
        const double dy = y_[b] - (y_[a] - s.vy);
        const double dz = z_[b] - (z_[a] - s.vz);
        const double d_sq = dx * dx + dy * dy + dz * dz;
        if (d_sq < cutoff_sq_) {
            hit(a, b, index_[a], s.s[0] + image_[3 * a], s.s[1] + image_[3 * a + 1],
                s.s[2] + image_[3 * a + 2], s, dx, dy, dz, d_sq);
        }
    }

    /// The pair (a, b) through each of shifts[0, count) (the direct backend: few atoms, many
    /// images). The same test, term for term, as pair() for each shift.
    void images(std::uint32_t a, std::uint32_t b, const ImageShift* shifts, std::size_t count) {
        tests_ += count;
        const double ax = x_[a], ay = y_[a], az = z_[a];
        const double bx = x_[b], by = y_[b], bz = z_[b];
        const std::uint32_t i = index_[a];
        const int ia = image_[3 * a], ib = image_[3 * a + 1], ic = image_[3 * a + 2];
        for (std::size_t k = 0; k < count; ++k) {
            const ImageShift& s = shifts[k];
            const double dx = bx - (ax - s.vx);
            const double dy = by - (ay - s.vy);
            const double dz = bz - (az - s.vz);
            const double d_sq = dx * dx + dy * dy + dz * dz;
            if (d_sq < cutoff_sq_) {
                hit(a, b, i, s.s[0] + ia, s.s[1] + ib, s.s[2] + ic, s, dx, dy, dz, d_sq);
            }
        }
    }

    /// The wrapped Cartesian position of atom a (the one the tests use).
    Eigen::Vector3d position(std::uint32_t a) const { return {x_[a], y_[a], z_[a]}; }

    /// Distance tests so far (for the work model's measurements).
    std::uint64_t tests() const { return tests_; }

  private:
    void scan(std::uint32_t a, std::uint32_t from, std::uint32_t to, double ax, double ay,
              double az, const ImageShift& s) {
        std::uint32_t hits[kernel_block + 4];
        double hit_d_sq[kernel_block + 4];
        // What a hit needs of atom a, looked up once per range rather than once per pair (the
        // image arithmetic was ~30 of the ~120 instructions per stored pair on diamond Si).
        const std::uint32_t i = index_[a];
        const int sa = s.s[0] + image_[3 * a];
        const int sb = s.s[1] + image_[3 * a + 1];
        const int sc = s.s[2] + image_[3 * a + 2];
        for (std::uint32_t start = from; start < to; start += kernel_block) {
            const std::uint32_t count = std::min(kernel_block, to - start);
            const double* xs = x_ + start;
            const double* ys = y_ + start;
            const double* zs = z_ + start;
            const std::uint32_t found =
                within_cutoff(xs, ys, zs, count, ax, ay, az, cutoff_sq_, hits, hit_d_sq);
            for (std::uint32_t h = 0; h < found; ++h) {
                const std::uint32_t k = hits[h];
                hit(a, start + k, i, sa, sb, sc, s, xs[k] - ax, ys[k] - ay, zs[k] - az,
                    hit_d_sq[h]);
            }
        }
    }

    // A hit (a, b) through s; i is a's caller index and (sa_a, sb_a, sc_a) = s + image of a.
    void hit(std::uint32_t a, std::uint32_t b, std::uint32_t i, int sa_a, int sb_a, int sc_a,
             const ImageShift& s, double dx, double dy, double dz, double d_sq) {
        std::uint32_t j = index_[b];
        int sa = sa_a - image_[3 * b];
        int sb = sb_a - image_[3 * b + 1];
        int sc = sc_a - image_[3 * b + 2];
        if (half_ && flip(i, j, sa, sb, sc)) {
            // Report (j, i, -S), with D computed in that orientation, x_a - (x_b - H (-s)), so
            // that d and D do not depend on which atom a backend happened to scan first (the
            // contract: identical d and D whatever the backend). The test is redone on it.
            std::swap(i, j);
            sa = -sa;
            sb = -sb;
            sc = -sc;
            dx = x_[a] - (x_[b] + s.vx);
            dy = y_[a] - (y_[b] + s.vy);
            dz = z_[a] - (z_[b] + s.vz);
            d_sq = dx * dx + dy * dy + dz * dz;
            if (!(d_sq < cutoff_sq_)) {
                return;
            }
        }
        if (!rule_.uniform() && !rule_.accepts(i, j, d_sq)) {
            return;
        }
        sink_.add(i, j, sa, sb, sc, dx, dy, dz, d_sq);
    }

    // Half lists keep (i, j, S) with i < j, or i == j with S lexicographically positive in the
    // caller's frame; true when the found orientation is the other one.
    bool flip(std::uint32_t i, std::uint32_t j, int sa, int sb, int sc) const {
        if (i != j) {
            return i > j;
        }
        Eigen::Vector3i caller(sa, sb, sc);
        if (reduced_frame_) {
            caller = to_caller_ * caller;
        }
        return caller[0] < 0 ||
               (caller[0] == 0 && (caller[1] < 0 || (caller[1] == 0 && caller[2] < 0)));
    }

    const double* x_;
    const double* y_;
    const double* z_;
    const std::int32_t* image_;
    const std::uint32_t* index_;
    Eigen::Matrix3d h_;
    double cutoff_sq_;
    const CutoffRule& rule_;
    bool half_;
    Eigen::Matrix3i to_caller_;
    bool reduced_frame_;
    PairSink& sink_;
    std::uint64_t tests_ = 0;
};

} // namespace tricell::detail
