// The shared inner loop of every backend: a backend names candidate (atom range, atom range,
// image shift) triples in its own atom order, or a home cell's atoms with all its ranges at once
// (cell(), through the range kernel of range_kernel.hpp for a uniform cutoff), and the
// CandidateScanner tests them against the cutoff through the run-time selected distance
// kernel, turns each hit into the caller's indices
// and an image shift relative to the caller's positions, applies a variable cutoff when there is
// one, orients half-list pairs canonically and hands them to the PairSink.
//
// Positions live in an AtomTable (atom_table.hpp). A pair (a, b) found through the cell shift s
// has, for the caller, S = s + image_a - image_b and D = (x_b - x_a) + T with T = H s in the search
// frame, rounded in exactly that order (the positions' difference first, then the translation) and
// a zero component stored as +0. IEEE rounding is symmetric (fl(p - q) = -fl(q - p), and T of -s is
// exactly -T), so the same pair found from b is (b, a) through -s with exactly -D and the same d^2:
// D is a function of (i, j, S) alone, whichever atom a backend scans first, and a half list turns a
// pair into its canonical orientation by negating D, computing nothing again.
//
// A subset search (NeighborOptions::query) scans from the query atoms only (subset_scan.hpp).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "frame/search_frame.hpp"
#include "scan/atom_table.hpp"
#include "scan/cutoff_rule.hpp"
#include "scan/distance_kernel.hpp"
#include "scan/half_orientation.hpp"
#include "scan/pair_sink.hpp"
#include "scan/range_kernel.hpp"

namespace tricell::detail {

/// An image shift s (search frame) and its Cartesian vector H s.
struct ImageShift {
    int s[3];
    double v[3];
};

/// Images side by side with their translations as columns (the direct backend's, for
/// within_images()): image k is shifts[k], its T is (x[k], y[k], z[k]).
struct ImageColumns {
    const ImageShift* shifts;
    const double* x;
    const double* y;
    const double* z;
    ImageColumns from(std::size_t k) const { return {shifts + k, x + k, y + k, z + k}; }
};

class CandidateScanner {
  public:
    /// Scans `atoms` (in `frame`'s box) for the pairs `rule` takes, of a full or a `half` list
    /// (a subset one when the table has query flags), into `sink`. `mirrored`: a full list of
    /// BuildPlan::mirrored, whose backend names each unordered pair once, as for a half list,
    /// and each hit is stored as found and then turned around (-S, -D, the same d).
    CandidateScanner(const AtomTable& atoms, const SearchFrame& frame, const CutoffRule& rule,
                     bool half, bool mirrored, PairSink& sink)
        : x_(atoms.x.data()), y_(atoms.y.data()), z_(atoms.z.data()), image_(atoms.image.data()),
          zero_images_(atoms.zero_images), index_(atoms.index.data()), h_(frame.box().matrix()),
          cutoff_sq_(rule.threshold_sq()), rule_(rule), half_stencil_(half || mirrored),
          orient_(half && !mirrored), mirrored_(mirrored && !half), frame_(frame), sink_(sink),
          query_(atoms.subset() ? atoms.query.data() : nullptr),
          subset_half_(atoms.subset() && half), range_input_{x_,         y_,
                                                             z_,         index_,
                                                             image_,     zero_images_,
                                                             cutoff_sq_, half_stencil_,
                                                             orient_},
          range_kernel_(range_kernel()) {}

    /// Whether atom a can be the first atom of a pair (false only outside the query of a full
    /// subset list); backends that name single pairs skip the others early.
    bool wants(std::uint32_t a) const {
        return query_ == nullptr || subset_half_ || query_[a] != 0;
    }

    ImageShift shift(int sa, int sb, int sc) const {
        if ((sa | sb | sc) == 0) {
            return ImageShift{{0, 0, 0}, {0, 0, 0}}; // the same bits in every D (see above)
        }
        const Eigen::Vector3d v = h_.col(0) * sa + h_.col(1) * sb + h_.col(2) * sc;
        return ImageShift{{sa, sb, sc}, {v.x(), v.y(), v.z()}};
    }

    /// Every a in [a0, a1) with every b in [b0, b1) through `s`. With `own` the two ranges hold
    /// the same atoms through a zero shift (b0 <= a0, a1 <= b1): a full list skips b == a, the half
    /// stencil (a half or mirrored list) takes only b > a (then b0 == a0 is required, so each
    /// unordered pair is seen once).
    void ranges(std::uint32_t a0, std::uint32_t a1, std::uint32_t b0, std::uint32_t b1,
                const ImageShift& s, bool own) {
        if (subset_half_) {
            half_subset_ranges(a0, a1, b0, b1, s, own);
            return;
        }
        if (query_ != nullptr) {
            subset_ranges(a0, a1, b0, b1, s, own ? Scan::own : Scan::plain);
            return;
        }
        tests_ += std::uint64_t(a1 - a0) * std::uint64_t(b1 - b0);
        // Up to kernel_group atoms a in one kernel call. In the own range all of them are
        // tested against the same range and the pairs a full list skips (b == a) or the half
        // stencil leaves to the other atom (b < a) are dropped after the test: a few tests more,
        // against a kernel call per atom.
        std::uint32_t group[kernel_group];
        for (std::uint32_t a = a0; a < a1; a += kernel_group) {
            const std::uint32_t last = std::min(a + kernel_group, a1);
            for (std::uint32_t g = 0; g < last - a; ++g) {
                group[g] = a + g;
            }
            scan(group, last - a, own && half_stencil_ ? a + 1 : b0, b1, s,
                 own ? Scan::own : Scan::plain);
        }
    }

    /// Every atom of [a0, a1) against every range of list[0, count), the pieces of a home cell's
    /// stencil rows: through the range kernel (range_kernel.hpp), up to kernel_group atoms at a
    /// time (fewer where a claim of the sink holds fewer against the longest range) against as
    /// many ranges as one claim holds; a variable cutoff, a subset search and a range too long
    /// for a claim go range by range through ranges().
    void cell(std::uint32_t a0, std::uint32_t a1, CandidateRange* list, std::uint32_t count) {
        if (query_ != nullptr || !rule_.uniform()) {
            for (std::uint32_t q = 0; q < count; ++q) {
                ranges(a0, a1, list[q].b0, list[q].b1, image_shift(list[q]), list[q].own);
            }
            return;
        }
        for (std::uint32_t q = 0; q < count; ++q) {
            CandidateRange& r = list[q];
            r.self_turn = orient_ && flip(0, 0, r.s[0], r.s[1], r.s[2]);
            if (range_input_.boxes != nullptr) {
                r.reach_sq = cell_reach_sq(cutoff_, box_bound_, r.v);
            }
        }
        // As many atoms at a time as a claim holds against the longest range (block mode claims
        // a block at most; a mirrored list stores each hit twice).
        std::size_t longest = 1;
        for (std::uint32_t q = 0; q < count; ++q) {
            longest = std::max<std::size_t>(longest, list[q].b1 - list[q].b0);
        }
        const std::size_t room = (sink_.claim_limit() - kernel_slack) / stores_per_hit();
        const auto step = std::uint32_t(std::clamp<std::size_t>(room / longest, 1, kernel_group));
        for (std::uint32_t g0 = a0; g0 < a1; g0 += step) {
            const std::uint32_t g1 = std::min(g0 + step, a1);
            const std::size_t most = room / (g1 - g0);
            std::uint32_t first = 0;
            std::size_t candidates = 0;
            for (std::uint32_t q = 0; q < count; ++q) {
                const std::size_t length = list[q].b1 - list[q].b0;
                if (candidates + length > most) {
                    kernel_ranges(g0, g1, list + first, q - first, candidates);
                    first = q;
                    candidates = 0;
                }
                if (length > most) {
                    ranges(g0, g1, list[q].b0, list[q].b1, image_shift(list[q]), list[q].own);
                    first = q + 1;
                    continue;
                }
                candidates += length;
            }
            kernel_ranges(g0, g1, list + first, count - first, candidates);
        }
    }

    /// Prunes cell() by the bounding boxes of clusters of atoms: 6 per cluster (lower x, y, z,
    /// upper x, y, z of the atoms' positions here), cluster c holding atoms [starts[c],
    /// starts[c + 1]), `bound` the largest magnitude of a coordinate; each range of cell() then
    /// names its clusters.
    void prune_by_clusters(const double* boxes, const std::uint32_t* starts, double bound) {
        range_input_.boxes = boxes;
        range_input_.cluster_start = starts;
        box_bound_ = bound;
    }

    /// The atoms' positions (for a backend's boxes of them).
    const double* x() const { return x_; }
    const double* y() const { return y_; }
    const double* z() const { return z_; }

    /// One candidate pair (a, b) through `s` (backends without contiguous ranges).
    void pair(std::uint32_t a, std::uint32_t b, const ImageShift& s) {
        if (query_ != nullptr && query_[a] == 0) {
            if (subset_half_ && query_[b] != 0) {
                test(b, a, reversed(s)); // a half subset list: from the query end
            }
            return;
        }
        test(a, b, s);
    }

    /// The pair (a, b) through each of shifts[0, count) (the direct backend: few atoms, many
    /// images). The same test, term for term, as pair() for each shift. The images are tested
    /// a chunk at a time by within_images() (a vector kernel where the processor has one), and
    /// each hit is written straight into the slots claimed for atom a, from what the pair (a, b)
    /// shares (i, j, the images' difference) and the image's s and T. The pairs of one atom a
    /// take one claim and their square roots are taken together, when the claim fills up, when a
    /// changes and at flush_images().
    void images(std::uint32_t a, std::uint32_t b, const ImageColumns& shifts, std::size_t count) {
        if (subset_half_ && query_[a] == 0) {
            for (std::size_t k = 0; k < count && query_[b] != 0; ++k) {
                pair(a, b, shifts.shifts[k]);
            }
            return;
        }
        if (!wants(a)) {
            return;
        }
        if (a != images_a_) {
            flush_images();
            images_a_ = a;
        }
        tests_ += count;
        const double d0[3] = {x_[b] - x_[a], y_[b] - y_[a], z_[b] - z_[a]};
        const std::uint32_t i = index_[a], j = index_[b];
        const int ia = image_[3 * a], ib = image_[3 * a + 1], ic = image_[3 * a + 2];
        const int ja = image_[3 * b], jb = image_[3 * b + 1], jc = image_[3 * b + 2];
        for (std::size_t k0 = 0; k0 < count; k0 += images_chunk) {
            const std::uint32_t chunk =
                std::uint32_t(std::min<std::size_t>(count - k0, images_chunk));
            std::uint32_t k[images_chunk + kernel_slack];
            const std::uint32_t found =
                within_images(shifts.x + k0, shifts.y + k0, shifts.z + k0, chunk, d0, cutoff_sq_, k,
                              images_d_sq_ + images_kept_);
            if (found == 0) {
                continue;
            }
            if (images_kept_ + found > images_room_) {
                // a fresh claim: the hits' d^2 move to the front of images_d_sq_
                const std::uint32_t from = images_kept_;
                flush_images();
                if (from != 0) {
                    std::copy(images_d_sq_ + from, images_d_sq_ + from + found, images_d_sq_);
                }
                images_out_ = sink_.claim(stores_per_hit() * images_claim);
                images_room_ = images_claim;
            }
            std::uint32_t n = images_kept_;
            for (std::uint32_t h = 0; h < found; ++h) {
                const ImageShift& s = shifts.shifts[k0 + k[h]];
                Hit p{i,
                      j,
                      (s.s[0] + ia) - ja,
                      (s.s[1] + ib) - jb,
                      (s.s[2] + ic) - jc,
                      d0[0] + s.v[0],
                      d0[1] + s.v[1],
                      d0[2] + s.v[2],
                      images_d_sq_[images_kept_ + h]};
                if (counts(p, b)) {
                    PairSink::put(images_out_, n, p.i, p.j, p.sa, p.sb, p.sc, p.dx + 0.0,
                                  p.dy + 0.0, p.dz + 0.0);
                    images_d_sq_[n++] = p.d_sq;
                }
            }
            images_kept_ = n;
        }
    }

    /// Stores the pairs images() wrote for atom a: their distances from the d^2 kept, then the
    /// commit (a backend calling images() calls this after each atom a, so that an atom's pairs
    /// stay within its work unit).
    void flush_images() {
        if (images_room_ == 0) {
            return;
        }
        PairSink::put_distances(images_out_, images_d_sq_, images_kept_);
        commit_hits(images_out_, images_kept_);
        images_kept_ = images_room_ = 0;
    }

    /// The wrapped Cartesian position of atom a (the one the tests use).
    Eigen::Vector3d position(std::uint32_t a) const { return {x_[a], y_[a], z_[a]}; }

    /// Distance tests so far (for the work model's measurements).
    std::uint64_t tests() const { return tests_; }

  private:
    // What a hit needs of the atoms a of one scan, looked up once per scan rather than once per
    // pair (the image arithmetic was ~30 of the ~120 instructions per stored pair on diamond
    // Si): the position and, for the caller, the index and s + image.
    struct Side {
        std::uint32_t a[kernel_group]; ///< the atoms, in the backend's order
        double x[kernel_group], y[kernel_group], z[kernel_group];
        std::uint32_t i[kernel_group];
        int sa[kernel_group], sb[kernel_group], sc[kernel_group];
    };

    // How scan() treats the hits of one range: `own` drops those ranges() does not take in the
    // own range; `to_others` (a half subset list scanning from the query atoms of the second
    // range) keeps only those whose second atom is outside the query.
    enum class Scan { plain, own, to_others };

    // The test of pair() once a first atom is chosen.
    void test(std::uint32_t a, std::uint32_t b, const ImageShift& s) {
        ++tests_;
        const double dx = (x_[b] - x_[a]) + s.v[0];
        const double dy = (y_[b] - y_[a]) + s.v[1];
        const double dz = (z_[b] - z_[a]) + s.v[2];
        const double d_sq = dx * dx + dy * dy + dz * dz;
        if (d_sq < cutoff_sq_) {
            hit(b, index_[a], s.s[0] + image_[3 * a], s.s[1] + image_[3 * a + 1],
                s.s[2] + image_[3 * a + 2], dx, dy, dz, d_sq);
        }
    }

    // The subset search's part (subset_scan.hpp).
    void half_subset_ranges(std::uint32_t a0, std::uint32_t a1, std::uint32_t b0, std::uint32_t b1,
                            const ImageShift& s, bool own);
    void subset_ranges(std::uint32_t a0, std::uint32_t a1, std::uint32_t b0, std::uint32_t b1,
                       const ImageShift& s, Scan how);
    bool may_turn(Scan how, std::uint32_t start, const std::uint32_t* hits,
                  std::uint32_t found) const;
    std::uint32_t drop_queried(std::uint32_t start, std::uint32_t* hits, double* d_sq,
                               std::uint32_t found) const;
    std::uint32_t drop_mirrored(const Side& side, std::uint32_t start, std::uint32_t* hits,
                                double* d_sq, std::uint32_t found) const;

    // Atoms [a0, a1) against ranges list[0, count) of `candidates` atoms in all, through the range
    // kernel in one claim.
    void kernel_ranges(std::uint32_t a0, std::uint32_t a1, const CandidateRange* list,
                       std::uint32_t count, std::size_t candidates) {
        if (count == 0) {
            return;
        }
        const PairSink::Slots out =
            sink_.claim(stores_per_hit() * (a1 - a0) * candidates + kernel_slack);
        commit_hits(out, range_kernel_(range_input_, a0, a1, list, count, out, tests_));
    }

    static ImageShift image_shift(const CandidateRange& r) {
        return ImageShift{{r.s[0], r.s[1], r.s[2]}, {r.v[0], r.v[1], r.v[2]}};
    }

    // -s (T of -s is exactly -T, see above).
    static ImageShift reversed(const ImageShift& s) {
        return ImageShift{{-s.s[0], -s.s[1], -s.s[2]}, {-s.v[0], -s.v[1], -s.v[2]}};
    }

    // Atoms group[0, count) (at most kernel_group, ascending) against b in [from, to) through
    // s, one kernel block at a time, the hits filtered as `how` says.
    void scan(const std::uint32_t* atoms, std::uint32_t group, std::uint32_t from, std::uint32_t to,
              const ImageShift& s, Scan how) {
        if (from >= to) {
            return;
        }
        Side side;
        for (std::uint32_t g = 0; g < group; ++g) {
            const std::uint32_t a = atoms[g];
            side.a[g] = a;
            side.x[g] = x_[a];
            side.y[g] = y_[a];
            side.z[g] = z_[a];
            side.i[g] = index_[a];
            side.sa[g] = s.s[0] + image_[3 * a];
            side.sb[g] = s.s[1] + image_[3 * a + 1];
            side.sc[g] = s.s[2] + image_[3 * a + 2];
        }
        std::uint32_t hits[kernel_group * kernel_block + kernel_slack];
        double hit_d_sq[kernel_group * kernel_block + kernel_slack];
        for (std::uint32_t start = from; start < to; start += kernel_block) {
            const std::uint32_t count = std::min(kernel_block, to - start);
            std::uint32_t found =
                within_cutoff_group(x_ + start, y_ + start, z_ + start, count, side.x, side.y,
                                    side.z, group, s.v, cutoff_sq_, hits, hit_d_sq);
            if (how == Scan::own) {
                found = drop_others(side, start, hits, hit_d_sq, found);
                if (subset_half_) {
                    found = drop_mirrored(side, start, hits, hit_d_sq, found);
                }
            } else if (how == Scan::to_others) {
                found = drop_queried(start, hits, hit_d_sq, found);
            }
            if (found == 0) {
                continue;
            }
            if (!rule_.uniform()) {
                keep_some(side, start, hits, hit_d_sq, found, s);
            } else if (!orient_ || !may_turn(how, start, hits, found)) {
                keep_all(side, start, hits, hit_d_sq, found, s);
            } else if (query_ == nullptr) {
                keep_oriented<false>(side, start, hits, hit_d_sq, found, s);
            } else {
                keep_oriented<true>(side, start, hits, hit_d_sq, found, s);
            }
        }
    }

    // Drops the own range's hits (a, b) that ranges() does not take: b == a, and b < a in a
    // half list (not a subset one, which scans its own range as a full list). Returns how many
    // remain (in order).
    std::uint32_t drop_others(const Side& side, std::uint32_t start, std::uint32_t* hits,
                              double* d_sq, std::uint32_t found) const {
        const bool later = half_stencil_ && query_ == nullptr;
        std::uint32_t kept = 0;
        for (std::uint32_t h = 0; h < found; ++h) {
            const std::uint32_t a = side.a[hits[h] / kernel_block];
            const std::uint32_t b = start + hits[h] % kernel_block;
            hits[kept] = hits[h];
            d_sq[kept] = d_sq[h];
            kept += (later ? b > a : b != a) ? 1u : 0u;
        }
        return kept;
    }

    // The hits of a block with a variable cutoff, which drops some: pair by pair (oriented for
    // a half list), with the block's places claimed once, D computed only when stored and the
    // square roots taken together at the end.
    void keep_some(const Side& side, std::uint32_t start, const std::uint32_t* hits,
                   const double* d_sq, std::uint32_t found, const ImageShift& s) {
        const PairSink::Slots out = sink_.claim(found);
        double kept_d_sq[kernel_group * kernel_block];
        std::uint32_t kept = 0;
        for (std::uint32_t h = 0; h < found; ++h) {
            const std::uint32_t g = hits[h] / kernel_block;
            const std::uint32_t b = start + hits[h] % kernel_block;
            Hit p = make_hit(b, side.i[g], side.sa[g], side.sb[g], side.sc[g], 0, 0, 0, d_sq[h]);
            if (out.vectors != nullptr) {
                p.dx = (x_[b] - side.x[g]) + s.v[0];
                p.dy = (y_[b] - side.y[g]) + s.v[1];
                p.dz = (z_[b] - side.z[g]) + s.v[2];
            }
            if (!counts(p, b)) {
                continue;
            }
            PairSink::put(out, kept, p.i, p.j, p.sa, p.sb, p.sc, p.dx + 0.0, p.dy + 0.0,
                          p.dz + 0.0);
            kept_d_sq[kept++] = p.d_sq;
        }
        PairSink::put_distances(out, kept_d_sq, kept);
        sink_.commit(kept);
    }

    // A half list with a uniform cutoff keeps every hit of a block, each in its canonical
    // orientation. Which orientation a pair takes is a coin toss (caller indices against the
    // backend's order), so i, j, S and D of either are written without a branch: a pair turned
    // around has i and j swapped, -S and -D (exact, see above) and the same d. As in keep_all(),
    // each column is filled by its own loop; the orientation is decided with i and j (only an
    // atom's own image, i == j, needs S).
    // (Subset: a subset list's, which turns only pairs of two query atoms, see orients().)
    template <bool Subset>
    void keep_oriented(const Side& side, std::uint32_t start, const std::uint32_t* hits,
                       const double* d_sq, std::uint32_t found, const ImageShift& s) {
        const PairSink::Slots out = sink_.claim(found);
        std::int32_t sign[kernel_group * kernel_block]; // -1: turned around
        for (std::uint32_t h = 0; h < found; ++h) {
            const std::uint32_t g = hits[h] / kernel_block;
            const std::uint32_t b = start + hits[h] % kernel_block;
            const std::uint32_t i = side.i[g], j = index_[b];
            bool other = i > j;
            if (__builtin_expect(i == j, 0)) {
                other = flip(i, j, side.sa[g] - image_[3 * b], side.sb[g] - image_[3 * b + 1],
                             side.sc[g] - image_[3 * b + 2]);
            }
            other = other && (!Subset || query_[b] != 0);
            out.i[h] = other ? j : i;
            out.j[h] = other ? i : j;
            sign[h] = other ? -1 : 1;
        }
        if (out.shifts != nullptr && zero_images_) {
            for (std::uint32_t h = 0; h < found; ++h) {
                out.shifts[3 * h] = sign[h] * s.s[0];
                out.shifts[3 * h + 1] = sign[h] * s.s[1];
                out.shifts[3 * h + 2] = sign[h] * s.s[2];
            }
        } else if (out.shifts != nullptr) {
            for (std::uint32_t h = 0; h < found; ++h) {
                const std::uint32_t g = hits[h] / kernel_block;
                const std::int32_t* image =
                    image_ + 3 * std::size_t(start + hits[h] % kernel_block);
                out.shifts[3 * h] = sign[h] * (side.sa[g] - image[0]);
                out.shifts[3 * h + 1] = sign[h] * (side.sb[g] - image[1]);
                out.shifts[3 * h + 2] = sign[h] * (side.sc[g] - image[2]);
            }
        }
        PairSink::put_distances(out, d_sq, found);
        if (out.vectors != nullptr) {
            for (std::uint32_t h = 0; h < found; ++h) {
                const std::uint32_t g = hits[h] / kernel_block;
                const std::uint32_t b = start + hits[h] % kernel_block;
                const double turn = sign[h];
                out.vectors[3 * h] = turn * ((x_[b] - side.x[g]) + s.v[0]) + 0.0;
                out.vectors[3 * h + 1] = turn * ((y_[b] - side.y[g]) + s.v[1]) + 0.0;
                out.vectors[3 * h + 2] = turn * ((z_[b] - side.z[g]) + s.v[2]) + 0.0;
            }
        }
        sink_.commit(found);
    }

    // A full list with a uniform cutoff keeps every hit of a block as it is, so each column is
    // filled by its own short loop (pair by pair through PairSink::put(), the branches per
    // stored column and the scalar square root cost more than the stores themselves).
    void keep_all(const Side& side, std::uint32_t start, const std::uint32_t* hits,
                  const double* d_sq, std::uint32_t found, const ImageShift& s) {
        const PairSink::Slots out = sink_.claim(stores_per_hit() * found);
        for (std::uint32_t h = 0; h < found; ++h) {
            out.i[h] = side.i[hits[h] / kernel_block];
            out.j[h] = index_[start + hits[h] % kernel_block];
        }
        if (out.shifts != nullptr && zero_images_) {
            for (std::uint32_t h = 0; h < found; ++h) {
                out.shifts[3 * h] = s.s[0];
                out.shifts[3 * h + 1] = s.s[1];
                out.shifts[3 * h + 2] = s.s[2];
            }
        } else if (out.shifts != nullptr) {
            for (std::uint32_t h = 0; h < found; ++h) {
                const std::uint32_t g = hits[h] / kernel_block;
                const std::int32_t* image =
                    image_ + 3 * std::size_t(start + hits[h] % kernel_block);
                out.shifts[3 * h] = side.sa[g] - image[0];
                out.shifts[3 * h + 1] = side.sb[g] - image[1];
                out.shifts[3 * h + 2] = side.sc[g] - image[2];
            }
        }
        PairSink::put_distances(out, d_sq, found);
        if (out.vectors != nullptr) {
            for (std::uint32_t h = 0; h < found; ++h) {
                const std::uint32_t g = hits[h] / kernel_block;
                const std::uint32_t b = start + hits[h] % kernel_block;
                out.vectors[3 * h] = ((x_[b] - side.x[g]) + s.v[0]) + 0.0;
                out.vectors[3 * h + 1] = ((y_[b] - side.y[g]) + s.v[1]) + 0.0;
                out.vectors[3 * h + 2] = ((z_[b] - side.z[g]) + s.v[2]) + 0.0;
            }
        }
        commit_hits(out, found);
    }

    // A candidate within the cutoff, as it would be stored: i, j, S (s plus the images), D, d^2.
    struct Hit {
        std::uint32_t i, j;
        int sa, sb, sc;
        double dx, dy, dz, d_sq;
    };

    // The hit of b and the atom with caller index i whose s + image is (sa_a, sb_a, sc_a).
    Hit make_hit(std::uint32_t b, std::uint32_t i, int sa_a, int sb_a, int sc_a, double dx,
                 double dy, double dz, double d_sq) const {
        return Hit{i,
                   index_[b],
                   sa_a - image_[3 * b],
                   sb_a - image_[3 * b + 1],
                   sc_a - image_[3 * b + 2],
                   dx,
                   dy,
                   dz,
                   d_sq};
    }

    // Whether hit p counts, oriented for a half list: a half list reports (j, i, -S) with -D
    // when that is the canonical orientation (exactly what the other orientation's scan
    // computes, see above). Then a variable cutoff decides. (b: the second atom, see orients().)
    bool counts(Hit& p, std::uint32_t b) const {
        if (orient_ && orients(b) && flip(p.i, p.j, p.sa, p.sb, p.sc)) {
            std::swap(p.i, p.j);
            p.sa = -p.sa;
            p.sb = -p.sb;
            p.sc = -p.sc;
            p.dx = -p.dx;
            p.dy = -p.dy;
            p.dz = -p.dz;
        }
        return rule_.uniform() || rule_.accepts(p.i, p.j, p.d_sq);
    }

    // A hit (a, b) through s found one pair at a time.
    void hit(std::uint32_t b, std::uint32_t i, int sa_a, int sb_a, int sc_a, double dx, double dy,
             double dz, double d_sq) {
        Hit p = make_hit(b, i, sa_a, sb_a, sc_a, dx, dy, dz, d_sq);
        if (counts(p, b)) {
            sink_.add(p.i, p.j, p.sa, p.sb, p.sc, p.dx + 0.0, p.dy + 0.0, p.dz + 0.0, p.d_sq);
            if (mirrored_) {
                sink_.add(p.j, p.i, -p.sa, -p.sb, -p.sc, -p.dx + 0.0, -p.dy + 0.0, -p.dz + 0.0,
                          p.d_sq);
            }
        }
    }

    // Pairs a hit takes in the sink: two in a mirrored list.
    std::size_t stores_per_hit() const { return mirrored_ ? 2 : 1; }

    // Keeps the `found` pairs written to `out`, followed in a mirrored list by each turned around.
    void commit_hits(const PairSink::Slots& out, std::uint32_t found) {
        if (mirrored_) {
            PairSink::put_turned(out, found);
        }
        sink_.commit(stores_per_hit() * found);
    }

    // Whether a half list turns a hit (a, b) into its canonical orientation: always, but in a
    // subset list only when b is a query atom (a is one; otherwise the pair stays as found).
    bool orients(std::uint32_t b) const { return query_ == nullptr || query_[b] != 0; }

    // Half lists keep (i, j, S) with i < j, or i == j with S lexicographically positive in the
    // caller's frame; true when the found orientation is the other one.
    bool flip(std::uint32_t i, std::uint32_t j, int sa, int sb, int sc) const {
        if (i != j) {
            return i > j;
        }
        const Eigen::Vector3i caller = frame_.caller_shift(sa, sb, sc);
        return lexicographically_positive(-caller[0], -caller[1], -caller[2]);
    }

    const double* x_;
    const double* y_;
    const double* z_;
    const std::int32_t* image_;
    bool zero_images_;
    const std::uint32_t* index_;
    Eigen::Matrix3d h_;
    double cutoff_sq_;
    double cutoff_ = std::sqrt(cutoff_sq_);
    double box_bound_ = 0;
    const CutoffRule& rule_;
    bool half_stencil_; // the backend names each unordered pair once (a half or mirrored list)
    bool orient_;       // each pair is turned into its canonical orientation (a half list)
    bool mirrored_;     // each pair is stored twice, as found and turned around
    const SearchFrame& frame_;
    PairSink& sink_;
    const std::uint8_t* query_; // null unless a subset search (see above)
    bool subset_half_;
    RangeScanInput range_input_;
    RangeKernel range_kernel_;
    std::uint64_t tests_ = 0;
    // images(): the atom a of the pairs written since the last flush_images(), the slots claimed
    // for them (images_room_ pairs, 0: none claimed), how many are written and their d^2. A chunk
    // of images is tested at a time, and its hits always fit a fresh claim.
    static constexpr std::uint32_t images_chunk = 64, images_claim = 4 * images_chunk;
    std::uint32_t images_a_ = 0;
    PairSink::Slots images_out_{};
    std::uint32_t images_kept_ = 0, images_room_ = 0;
    double images_d_sq_[images_claim + images_chunk + kernel_slack];
};

} // namespace tricell::detail

#include "scan/subset_scan.hpp" // IWYU pragma: keep (the subset part of CandidateScanner)
