// The reference search of verify(). Brute force: every ordered atom pair through every image
// shift S whose fractional reach the perpendicular widths allow (|(s_j - s_i + S)_k| <= d / w_k,
// so S_k lies within cutoff / w_k of s_i - s_j), with D = x_j - x_i + H S computed from the
// caller's positions exactly as the contract defines it. Its cost is N^2 times the images per
// pair; above brute_force_budget distance tests the reference is tricell's own search with a
// backend the automatic choice does not take (the dense grid, or the compact hash when the
// automatic choice is the dense grid), whose binning and candidate enumeration share nothing
// with the automatic one's.
#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

#include "tricell/verify.hpp"
#include "verify/reference.hpp"

namespace tricell::detail {

PairCutoff::PairCutoff(const NeighborOptions& options) : options_(options) {
    if (!options.radii.empty()) {
        largest_ = 2 * *std::max_element(options.radii.begin(), options.radii.end());
        return;
    }
    if (options.species_cutoffs.empty()) {
        largest_ = options.cutoff;
        return;
    }
    std::map<std::int32_t, std::int32_t> index;
    for (const std::int32_t s : options.species) {
        index.emplace(s, 0);
    }
    for (auto& entry : index) {
        entry.second = std::int32_t(kind_count_++);
    }
    kinds_.reserve(options.species.size());
    for (const std::int32_t s : options.species) {
        kinds_.push_back(index[s]);
    }
    table_.assign(kind_count_ * kind_count_, 0.0);
    for (const SpeciesCutoff& entry : options.species_cutoffs) {
        const auto a = index.find(entry.a);
        const auto b = index.find(entry.b);
        if (a != index.end() && b != index.end()) {
            table_[std::size_t(a->second) * kind_count_ + std::size_t(b->second)] = entry.cutoff;
            table_[std::size_t(b->second) * kind_count_ + std::size_t(a->second)] = entry.cutoff;
            largest_ = std::max(largest_, entry.cutoff);
        }
    }
}

double PairCutoff::operator()(std::size_t i, std::size_t j) const {
    if (!options_.radii.empty()) {
        return options_.radii[i] + options_.radii[j];
    }
    if (options_.species_cutoffs.empty()) {
        return options_.cutoff;
    }
    return table_[std::size_t(kinds_[i]) * kind_count_ + std::size_t(kinds_[j])];
}

namespace {

// Images per atom pair the brute force visits, and whether every fractional coordinate is small
// enough for its integer shift ranges.
double brute_force_images(const Box& box, PointsView x, double cutoff) {
    double images = 1;
    for (int k = 0; k < 3; ++k) {
        if (box.periodic(k)) {
            images *= 2 * (cutoff / box.perpendicular_widths()[k]) + 2;
        }
    }
    for (std::size_t i = 0; i < x.size(); ++i) {
        if (!((box.inverse() * x[i]).cwiseAbs().maxCoeff() < 1e9)) {
            return INFINITY;
        }
    }
    return images;
}

std::vector<PairKey> brute_force(const Box& box, PointsView x, bool half,
                                 const PairCutoff& cutoff) {
    const std::size_t n = x.size();
    const double largest = cutoff.largest();
    const Eigen::Matrix3d& h = box.matrix();
    std::vector<Eigen::Vector3d> s(n);
    for (std::size_t i = 0; i < n; ++i) {
        s[i] = box.inverse() * x[i];
    }
    std::vector<PairKey> keys;
    for (std::size_t i = 0; i < n; ++i) {
        for (std::size_t j = half ? i : 0; j < n; ++j) {
            const double pair_cutoff = cutoff(i, j);
            if (!(pair_cutoff > 0)) {
                continue;
            }
            std::int64_t lo[3], hi[3];
            for (int k = 0; k < 3; ++k) {
                lo[k] = hi[k] = 0;
                if (box.periodic(k)) {
                    const double centre = s[i][k] - s[j][k];
                    const double reach =
                        largest / box.perpendicular_widths()[k] * (1 + 1e-9) + 1e-9;
                    lo[k] = std::int64_t(std::ceil(centre - reach));
                    hi[k] = std::int64_t(std::floor(centre + reach));
                }
            }
            for (std::int64_t a = lo[0]; a <= hi[0]; ++a) {
                for (std::int64_t b = lo[1]; b <= hi[1]; ++b) {
                    for (std::int64_t c = lo[2]; c <= hi[2]; ++c) {
                        const PairKey key{std::int64_t(i), std::int64_t(j), a, b, c};
                        if ((i == j && a == 0 && b == 0 && c == 0) ||
                            (half && !canonical_orientation(key))) {
                            continue;
                        }
                        const Eigen::Vector3d d =
                            x[j] - x[i] + h * Eigen::Vector3d(double(a), double(b), double(c));
                        if (d.norm() < pair_cutoff) {
                            keys.push_back(key);
                        }
                    }
                }
            }
        }
    }
    return keys;
}

} // namespace

ReferencePairs reference_pairs(const Box& box, PointsView positions, const NeighborOptions& options,
                               const PairCutoff& cutoff) {
    ReferencePairs out;
    const double n = double(positions.size());
    if (brute_force_images(box, positions, cutoff.largest()) * n * n <= brute_force_budget) {
        out.keys = brute_force(box, positions, options.half, cutoff);
        out.method = "brute force";
    } else {
        NeighborOptions search_options;
        search_options.cutoff = options.cutoff;
        search_options.radii = options.radii;
        search_options.species = options.species;
        search_options.species_cutoffs = options.species_cutoffs;
        search_options.half = options.half;
        // A full list grouped: through the full stencil, not the half one whose pairs the
        // checked search turns around.
        search_options.grouped = !options.half;
        search_options.threads = options.threads;
        search_options.max_pairs = options.max_pairs;
        search_options.max_bytes = options.max_bytes;
        search_options.quantities = Quantities{true, false, false};
        NeighborSearch search;
        search.build(box, positions, search_options);
        search_options.backend = search.info().backend == SearchBackend::dense
                                     ? SearchBackend::hash
                                     : SearchBackend::dense;
        search.build(box, positions, search_options);
        NeighborList list;
        search.compute(list);
        out.keys.reserve(list.size());
        for (std::size_t k = 0; k < list.size(); ++k) {
            const Shift shift = list.shift(k);
            out.keys.push_back(PairKey{list.i()[k], list.j()[k], shift[0], shift[1], shift[2]});
        }
        out.method = std::string("the ") + backend_name(search_options.backend) + " backend";
    }
    std::sort(out.keys.begin(), out.keys.end());
    return out;
}

} // namespace tricell::detail
