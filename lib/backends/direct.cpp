// The direct backend, for small systems: no grid, the periodic images are enumerated directly.
//
// In a cell smaller than the cutoff a grid has one cell per axis and a stencil of hundreds of
// offsets, each a separate image; the grid backends then scan a range of N atoms per (image,
// atom) and pay their per-range overhead (and the stencil's construction) hundreds of times for
// a few pairs each. Here bin() lists once the image shifts S whose translate T = H S can hold a
// pair at all (|T| < search radius + the largest distance between two wrapped atoms, found per
// row (sa, sb) as an interval of sc from a quadratic, then checked exactly), and visit() names
// every (a, b, S) candidate to the scanner one pair at a time. Candidates: N^2 x images, so
// this pays while that stays below the grid's N x stencil range scans (measured in issue 13: 1
// and 2 atoms ~10x fewer instructions than dense, 8 atoms at rc 10 1.5x, 64 atoms 3x more).
//
// Half lists take a < b through every image and a == b through the positive half of the images
// (the scanner orients what it is given canonically). The work units are the atoms a.
#include <algorithm>
#include <cmath>
#include <limits>

#include "backends/backend.hpp"

namespace tricell::detail {

namespace {

class DirectBackend final : public Backend {
  public:
    void bin(const BinningInput& input, std::vector<std::uint32_t>& order) override {
        const std::size_t n = input.fractional.size();
        half_ = input.options.half;
        atoms_ = n;
        order.resize(n);
        const Eigen::Matrix3d& h = input.frame.matrix();
        Eigen::Vector3d lo = Eigen::Vector3d::Zero(), hi = Eigen::Vector3d::Zero();
        for (std::size_t i = 0; i < n; ++i) {
            order[i] = std::uint32_t(i);
            const Eigen::Vector3d r = h * input.fractional[i];
            lo = i == 0 ? r : Eigen::Vector3d(lo.cwiseMin(r));
            hi = i == 0 ? r : Eigen::Vector3d(hi.cwiseMax(r));
        }
        // |D| >= |T| - |x_b - x_a| and |x_b - x_a| <= the diagonal of the atoms' bounding box
        // (plus a margin for the rounding between fractional and Cartesian positions).
        // Infinite when the spread is not finite (Cartesian positions near the largest double
        // on an open axis overflow to inf, and inf - inf is NaN): then every image within the
        // |S_k| bound below is a candidate.
        const double spread = (hi - lo).norm();
        const double reach = std::isfinite(spread)
                                 ? input.search_radius + spread * (1 + 1e-12) + 1e-12
                                 : std::numeric_limits<double>::infinity();
        // Along a periodic axis the wrapped fractional coordinates differ by less than 1, and
        // |D| >= w_k |(s_b - s_a + S)_k|, so |S_k| < r / w_k + 1 whatever the spread of the atoms
        // along open axes (which only loosens the |T| bound above).
        int m[3];
        for (int k = 0; k < 3; ++k) {
            const double w = input.frame.perpendicular_widths()[k];
            m[k] = input.frame.periodic(k)
                       ? checked_image_reach(
                             std::min(std::ceil(reach / w), std::ceil(input.search_radius / w) + 1),
                             input.search_radius, w, k)
                       : 0;
        }
        // S = 0 first, then S < 0, then S > 0 lexicographically (from positive_begin_).
        images_.assign(1, ImageShift{{0, 0, 0}, 0, 0, 0});
        const Eigen::Vector3d c = h.col(2);
        const double cc = c.squaredNorm();
        for (int pass = 0; pass < 2; ++pass) {
            for (int sa = -m[0]; sa <= m[0]; ++sa) {
                for (int sb = -m[1]; sb <= m[1]; ++sb) {
                    const Eigen::Vector3d row = h.col(0) * sa + h.col(1) * sb;
                    const double ac = row.dot(c);
                    const double disc = ac * ac - cc * (row.squaredNorm() - reach * reach);
                    if (disc < 0) {
                        continue;
                    }
                    const double root = std::sqrt(disc);
                    // Clamped as doubles before the cast: with c nearly orthogonal to a huge row
                    // the roots can lie far outside an int, on either side of [-m, m] (an
                    // interval wholly above or below it is empty); a NaN root (a row that
                    // overflowed) scans all of [-m, m], which the exact test below filters.
                    const auto bound = [](double v, double lo, double hi, double nan) {
                        return int(std::isnan(v) ? nan : std::clamp(v, lo, hi));
                    };
                    const double mc = m[2];
                    const int sc_lo = bound(std::floor((-ac - root) / cc) - 1, -mc, mc + 1, -mc);
                    const int sc_hi = bound(std::ceil((-ac + root) / cc) + 1, -mc - 1, mc, mc);
                    for (int sc = sc_lo; sc <= sc_hi; ++sc) {
                        const bool positive =
                            sa > 0 || (sa == 0 && (sb > 0 || (sb == 0 && sc > 0)));
                        if ((sa == 0 && sb == 0 && sc == 0) || positive != (pass == 1)) {
                            continue;
                        }
                        // the scanner's own shift vector, term for term
                        const Eigen::Vector3d t = h.col(0) * sa + h.col(1) * sb + h.col(2) * sc;
                        if (t.norm() < reach) {
                            images_.push_back(ImageShift{{sa, sb, sc}, t.x(), t.y(), t.z()});
                        }
                    }
                }
            }
            if (pass == 0) {
                positive_begin_ = images_.size();
            }
        }
    }

    std::size_t unit_count() const override { return atoms_; }

    void occupancy(UnitOccupancy& out) const override {
        // One atom per unit over 1/N of the box (so the pair estimate is the mean density's).
        out.atoms.assign(atoms_, 1.0);
        out.volume.assign(atoms_, atoms_ > 0 ? 1.0 / double(atoms_) : 1.0);
        out.neighbours = double(atoms_) * double(images_.size());
    }

    void visit(std::size_t begin, std::size_t end, CandidateScanner& scan) const override {
        const std::size_t images = images_.size();
        for (std::size_t a = begin; a < end; ++a) {
            const auto ua = std::uint32_t(a);
            // a == b: never through S = 0; a half list takes one of S and -S
            for (std::size_t k = half_ ? positive_begin_ : 1; k < images; ++k) {
                scan.pair(ua, ua, images_[k]);
            }
            for (std::size_t b = half_ ? a + 1 : 0; b < atoms_; ++b) {
                if (b == a) {
                    continue;
                }
                const auto ub = std::uint32_t(b);
                for (std::size_t k = 0; k < images; ++k) {
                    scan.pair(ua, ub, images_[k]);
                }
            }
        }
    }

    void describe(SearchInfo& info) const override {
        info.backend = SearchBackend::direct;
        info.cells = {{1, 1, 1}};
        info.stored_cells = 0;
    }

  private:
    bool half_ = false;
    std::size_t atoms_ = 0;
    std::vector<ImageShift> images_;
    std::size_t positive_begin_ = 0;
};

} // namespace

std::unique_ptr<Backend> make_direct_backend() {
    return std::make_unique<DirectBackend>();
}

} // namespace tricell::detail
