// The direct backend, for small systems: no grid, the periodic images are enumerated directly.
//
// In a cell smaller than the cutoff a grid has one cell per axis and a stencil of hundreds of
// offsets, each a separate image; the grid backends then scan a range of N atoms per (image,
// atom) and pay their per-range overhead (and the stencil's construction) hundreds of times for
// a few pairs each. Here bin() lists once the image shifts S whose translate T = H S can hold a
// pair at all (|T| < reach = search radius + the largest distance between two wrapped atoms,
// found per row (sa, sb) as an interval of sc from a quadratic, then checked exactly) and orders
// them by |T| into 64 buckets (a counting sort, stable). visit() then takes each pair (a, b) only
// through the images that can bring it within the radius, |T| < radius + |x_b - x_a| (the exact
// closest approach of that pair, |D| >= |T| - |x_b - x_a|): a prefix of the bucketed images, one
// lookup per pair, tested eight at a time from the images' translations as columns
// (within_images()); the hits of one atom a are stored together (CandidateScanner::images,
// flush_images). Candidates: N^2 x images,
// so this pays while that stays below the grid's N x stencil range scans (the cost model's
// choose_direct()).
// The images depend only on the frame, periodicity, radius and reach, so a pooled backend keeps
// them while those stay the same (the reach's atom spread is rounded up for that), and a search
// of one cell along a trajectory, or of the same cell again, skips the enumeration.
//
// Half lists, and full lists found through the half stencil (BuildPlan::mirrored), take a < b
// through every image and a == b through the positive half of the images (the scanner orients
// or turns around what it is given). Where S = 0 is the only image (a molecule,
// or a cutoff short of every image) of a few atoms, all atoms form one candidate range through
// the range kernel instead. The work units are the atoms a.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "backends/backend.hpp"
#include "policy/cost_model.hpp"

namespace tricell::detail {

namespace {

class DirectBackend final : public Backend {
  public:
    void bin(const BinningInput& input, std::vector<std::uint32_t>& order) override {
        const std::size_t n = input.fractional.size();
        half_ = input.plan.half_stencil(input.options);
        mirrored_ = input.plan.mirrored;
        atoms_ = n;
        search_radius_ = input.search_radius;
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
        // The diagonal is rounded up to a 16th of the radius: a longer reach only adds images
        // that no pair's own limit takes, and atoms moving inside a fixed cell then leave the
        // reach, and with it the images, unchanged from call to call. The reach is infinite when
        // the spread is not finite (Cartesian positions near the largest double on an open axis
        // overflow to inf, and inf - inf is NaN): then every image within the |S_k| bound below
        // is a candidate.
        const double diagonal = (hi - lo).norm() * (1 + 1e-12) + 1e-12;
        const double step = input.search_radius / 16;
        const double spread = step > 0 ? std::ceil(diagonal / step) * step : diagonal;
        const double reach = std::isfinite(spread) ? input.search_radius + spread
                                                   : std::numeric_limits<double>::infinity();
        if (same_images(input, reach)) {
            return; // the images of the last call (in the backend's own pooled object)
        }
        images_valid_ = false; // until the new images are complete
        reach_ = reach;
        // Along a periodic axis the wrapped fractional coordinates differ by less than 1, and
        // |D| >= w_k |(s_b - s_a + S)_k|, so |S_k| < r / w_k + 1 whatever the spread of the atoms
        // along open axes (which only loosens the |T| bound above).
        int m[3];
        for (int k = 0; k < 3; ++k) {
            const double w = input.frame.perpendicular_widths()[k];
            m[k] = input.frame.periodic(k)
                       ? checked_image_reach(std::min(std::ceil(reach_ / w),
                                                      std::ceil(input.search_radius / w) + 1),
                                             input.search_radius, w, k)
                       : 0;
        }
        double images = 1;
        for (int k = 0; k < 3; ++k) {
            images *= 2.0 * m[k] + 1;
        }
        if (images > max_direct_images) {
            fail<InvalidArgument>("search radius ", input.search_radius, " spans about ", images,
                                  " periodic images, more than the direct backend enumerates (",
                                  max_direct_images, "); choose a grid backend");
        }
        // Every image with |T| < reach, S = 0 first, with its bucket of |T|.
        reach_sq_ = reach_ * reach_;
        bucket_scale_ = double(buckets) / reach_sq_;
        found_.assign(1, Found{ImageShift{{0, 0, 0}, {0, 0, 0}}, 0, false});
        const Eigen::Vector3d c = h.col(2);
        const double cc = c.squaredNorm();
        const int any = m[0] + m[1] + m[2]; // 0: S = 0 is the only image (no periodic axis)
        for (int sa = -m[0]; any != 0 && sa <= m[0]; ++sa) {
            for (int sb = -m[1]; sb <= m[1]; ++sb) {
                const Eigen::Vector3d row = h.col(0) * sa + h.col(1) * sb;
                const double ac = row.dot(c);
                const double disc = ac * ac - cc * (row.squaredNorm() - reach_sq_);
                if (disc < 0) {
                    continue;
                }
                const double root = std::sqrt(disc);
                // Clamped as doubles before the cast: with c nearly orthogonal to a huge row the
                // roots can lie far outside an int, on either side of [-m, m] (an interval wholly
                // above or below it is empty); a NaN root (a row that overflowed) scans all of
                // [-m, m], which the exact test below filters.
                const auto bound = [](double v, double low, double high, double nan) {
                    return int(std::isnan(v) ? nan : std::clamp(v, low, high));
                };
                const double mc = m[2];
                const int sc_lo = bound(std::floor((-ac - root) / cc) - 1, -mc, mc + 1, -mc);
                const int sc_hi = bound(std::ceil((-ac + root) / cc) + 1, -mc - 1, mc, mc);
                for (int sc = sc_lo; sc <= sc_hi; ++sc) {
                    if (sa == 0 && sb == 0 && sc == 0) {
                        continue;
                    }
                    // the scanner's own shift vector, term for term
                    const Eigen::Vector3d t = row + c * sc;
                    const double norm_sq = t.squaredNorm();
                    if (norm_sq < reach_sq_) {
                        const bool positive =
                            sa > 0 || (sa == 0 && (sb > 0 || (sb == 0 && sc > 0)));
                        found_.push_back(Found{ImageShift{{sa, sb, sc}, {t.x(), t.y(), t.z()}},
                                               bucket(norm_sq), positive});
                    }
                }
            }
        }
        // A counting sort by bucket (stable: S = 0 stays first of `all_`).
        sort_by_bucket(false, all_);
        sort_by_bucket(true, positive_);
        images_h_ = h;
        for (int k = 0; k < 3; ++k) {
            images_periodic_[std::size_t(k)] = input.frame.periodic(k);
        }
        images_radius_ = input.search_radius;
        images_valid_ = true;
    }

    std::size_t unit_count() const override { return atoms_; }

    void occupancy(UnitOccupancy& out) const override {
        // One atom per unit over 1/N of the box (so the pair estimate is the mean density's).
        out.atoms.assign(atoms_, 1.0);
        out.volume.assign(atoms_, atoms_ > 0 ? 1.0 / double(atoms_) : 1.0);
    }

    double neighbours() const override { return double(atoms_) * double(all_.shifts.size()); }

    void visit(std::size_t begin, std::size_t end, CandidateScanner& scan) const override {
        if (all_.shifts.size() == 1 &&
            kernel_group * atoms_ + kernel_slack <= PairSink::block_size) {
            // Only S = 0 can hold a pair (a molecule, or a cutoff short of every image), and the
            // atoms are few: they are one range, tested in vector blocks. Any group of atoms
            // against it fits one claim, so the pairs come atom by atom whatever the split
            // between threads; a mirrored list, which turns a call's pairs around after them,
            // makes one call per atom for the same reason.
            const std::size_t step = mirrored_ ? 1 : end - begin;
            for (std::size_t a = begin; a < end; a += step) {
                CandidateRange range{half_ ? std::uint32_t(a) : 0u,
                                     std::uint32_t(atoms_),
                                     {0, 0, 0},
                                     {0, 0, 0},
                                     true,
                                     false};
                scan.cell(std::uint32_t(a), std::uint32_t(std::min(a + step, end)), &range, 1);
            }
            return;
        }
        for (std::size_t a = begin; a < end; ++a) {
            const auto ua = std::uint32_t(a);
            const Eigen::Vector3d xa = scan.position(ua);
            // a == b: never through S = 0; a half list takes one of S and -S
            if (half_) {
                scan.images(ua, ua, positive_.columns(), positive_.end[bucket_below(xa, xa, 0)]);
            } else {
                scan.images(ua, ua, all_.columns().from(1), all_.end[bucket_below(xa, xa, 0)] - 1);
            }
            for (std::size_t b = half_ ? a + 1 : 0; b < atoms_; ++b) {
                if (b == a) {
                    continue;
                }
                const auto ub = std::uint32_t(b);
                const Eigen::Vector3d xb = scan.position(ub);
                const double r = (xb - xa).norm();
                scan.images(ua, ub, all_.columns(), all_.end[bucket_below(xa, xb, r)]);
            }
            scan.flush_images();
        }
    }

    void describe(SearchInfo& info) const override {
        info.backend = SearchBackend::direct;
        info.cells = {{1, 1, 1}};
        info.stored_cells = 0;
    }

  private:
    static constexpr std::size_t buckets = 64;

    // True when the images of the last bin() serve this one: the same frame, periodicity,
    // radius and reach (all the enumeration reads).
    bool same_images(const BinningInput& input, double reach) const {
        if (!images_valid_ || reach != reach_ || input.search_radius != images_radius_ ||
            input.frame.matrix() != images_h_) {
            return false;
        }
        for (int k = 0; k < 3; ++k) {
            if (input.frame.periodic(k) != images_periodic_[std::size_t(k)]) {
                return false;
            }
        }
        return true;
    }

    // The bucket of an image of squared length `norm_sq`: [0, reach^2) in `buckets` equal slices
    // (monotone in the length, as a product with a positive constant rounds monotonically, so
    // every image shorter than a limit lies in the bucket of the limit's square or before; no
    // square root per image).
    std::size_t bucket(double norm_sq) const {
        const double q = norm_sq * bucket_scale_;
        return q < double(buckets - 1) ? std::size_t(q) : buckets - 1;
    }

    // No image longer than this can bring b within the search radius of a (|D| >= |T| - r, r the
    // computed |x_b - x_a|), with a margin far above the rounding of D, r and |T|.
    // The last bucket holding such images.
    std::size_t bucket_below(const Eigen::Vector3d& xa, const Eigen::Vector3d& xb, double r) const {
        const double scale = xa.cwiseAbs().sum() + xb.cwiseAbs().sum() + reach_;
        const double limit = (search_radius_ + r) * (1 + 1e-12) + 1e-12 * scale;
        return bucket(limit * limit);
    }

    // Images ordered by bucket of |T|, with their translations as columns too, and the end of
    // each bucket's run.
    struct Images {
        std::vector<ImageShift> shifts;
        std::vector<double> x, y, z;
        std::array<std::size_t, buckets> end{};
        ImageColumns columns() const { return {shifts.data(), x.data(), y.data(), z.data()}; }
    };

    // The found images (only the positive ones if `positive_only`) ordered by bucket into
    // `images`.
    void sort_by_bucket(bool positive_only, Images& images) const {
        std::array<std::size_t, buckets>& ends = images.end;
        ends.fill(0);
        for (const Found& f : found_) {
            if (!positive_only || f.positive) {
                ++ends[f.bucket];
            }
        }
        std::array<std::size_t, buckets> next{};
        std::size_t total = 0;
        for (std::size_t q = 0; q < buckets; ++q) {
            next[q] = total;
            total += ends[q];
            ends[q] = total;
        }
        images.shifts.resize(total);
        images.x.resize(total);
        images.y.resize(total);
        images.z.resize(total);
        for (const Found& f : found_) {
            if (!positive_only || f.positive) {
                const std::size_t k = next[f.bucket]++;
                images.shifts[k] = f.image;
                images.x[k] = f.image.v[0];
                images.y[k] = f.image.v[1];
                images.z[k] = f.image.v[2];
            }
        }
    }

    bool half_ = false;
    bool mirrored_ = false;
    std::size_t atoms_ = 0;
    double search_radius_ = 0;
    double reach_ = 1, reach_sq_ = 1, bucket_scale_ = double(buckets);
    // What the images were enumerated for (same_images()).
    bool images_valid_ = false;
    Eigen::Matrix3d images_h_ = Eigen::Matrix3d::Zero();
    std::array<bool, 3> images_periodic_{};
    double images_radius_ = 0;
    // Scratch of bin(): the images in enumeration order, each with its bucket and sign.
    struct Found {
        ImageShift image;
        std::size_t bucket;
        bool positive;
    };
    std::vector<Found> found_;
    // All images (S = 0 first) and the positive half, each ordered by bucket of |T|.
    Images all_, positive_;
};

} // namespace

std::unique_ptr<Backend> make_direct_backend() {
    return std::make_unique<DirectBackend>();
}

} // namespace tricell::detail
