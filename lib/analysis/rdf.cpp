// Rdf: per frame, a histogram of the half list's pair distances per ordered species pair
// (each pair (i, j, S) counts for (i, j) and for (j, i)), turned into that frame's g and n with
// the frame's own volume and counts (rdf.hpp gives the formulas), then added to running sums.
// Counts are integers, so a frame's g does not depend on the order pairs arrive in, hence not
// on the backend or the number of threads. A frame is validated and histogrammed into local
// arrays first; the sums change only once nothing can fail any more.
#include "tricell/analysis/rdf.hpp"

#include <algorithm>
#include <cmath>
#include <set>

#include "analysis/half_pairs.hpp"
#include "tricell/error.hpp"

namespace tricell {

namespace {

// The bin of d (0 <= d < rmax): the k with edges[k] <= d < edges[k + 1], exactly as the edges
// say (the first guess from d * bins / rmax can be one off by rounding).
std::size_t bin_of(double d, const std::vector<double>& edges) {
    const std::size_t bins = edges.size() - 1;
    std::size_t k = std::min(bins - 1, static_cast<std::size_t>(d / edges.back() * double(bins)));
    while (k > 0 && d < edges[k]) {
        --k;
    }
    while (k + 1 < bins && d >= edges[k + 1]) {
        ++k;
    }
    return k;
}

} // namespace

void RdfOptions::validate() const {
    if (!(std::isfinite(rmax) && rmax > 0)) {
        detail::fail<InvalidArgument>("RdfOptions::rmax must be finite and > 0 (got ", rmax, ")");
    }
    if (bins < 1 || bins > max_bins) {
        detail::fail<InvalidArgument>("RdfOptions::bins must be between 1 and ", max_bins, " (got ",
                                      bins, ")");
    }
    if (threads < 0) {
        detail::fail<InvalidArgument>("RdfOptions::threads must be >= 0 (got ", threads, ")");
    }
}

Rdf::Rdf(const RdfOptions& options) : options_(options) {
    options_.validate();
    edges_.resize(options_.bins + 1);
    for (std::size_t k = 0; k <= options_.bins; ++k) {
        edges_[k] = options_.rmax * double(k) / double(options_.bins);
    }
    edges_.back() = options_.rmax;
    total_.g.assign(options_.bins, 0.0);
    total_.n.assign(options_.bins, 0.0);
}

void Rdf::add_frame(const Box& box, PointsView positions,
                    const std::vector<std::int32_t>& species) {
    const std::size_t n_atoms = positions.size();
    for (int axis = 0; axis < 3; ++axis) {
        if (!box.periodic(axis)) {
            detail::fail<InvalidArgument>(
                "Rdf: axis ", "abc"[axis],
                " of the frame is not periodic; g(r) is normalised by the cell volume, which "
                "an open axis does not define");
        }
    }
    if (n_atoms == 0) {
        detail::fail<InvalidArgument>("Rdf: the frame has no atoms");
    }
    if (!species.empty() && species.size() != n_atoms) {
        detail::fail<InvalidArgument>("Rdf: species has ", species.size(), " entries for ", n_atoms,
                                      " positions");
    }
    // Dense indices of this frame's species, ascending.
    std::vector<std::int32_t> kinds;
    std::vector<std::uint32_t> kind_of(n_atoms, 0);
    if (species.empty()) {
        kinds.push_back(0);
    } else {
        for (std::size_t i = 0; i < n_atoms; ++i) {
            if (species[i] < 0) {
                detail::fail<InvalidArgument>("Rdf: species of atom ", i, " must be >= 0 (got ",
                                              species[i], ")");
            }
        }
        kinds = species;
        std::sort(kinds.begin(), kinds.end());
        kinds.erase(std::unique(kinds.begin(), kinds.end()), kinds.end());
        for (std::size_t i = 0; i < n_atoms; ++i) {
            kind_of[i] = std::uint32_t(std::lower_bound(kinds.begin(), kinds.end(), species[i]) -
                                       kinds.begin());
        }
    }
    const std::size_t n_kinds = kinds.size();
    std::vector<double> members(n_kinds, 0.0);
    for (std::size_t i = 0; i < n_atoms; ++i) {
        members[kind_of[i]] += 1;
    }

    // counts[(a * n_kinds + b) * bins + k]: ordered pairs (atom of a, atom of b) in bin k.
    const std::size_t bins = options_.bins;
    std::vector<std::uint64_t> counts(n_kinds * n_kinds * bins, 0);
    NeighborOptions search;
    search.cutoff = options_.rmax;
    search.threads = options_.threads;
    search.backend = options_.backend;
    detail::for_each_half_pair(
        box, positions, search,
        [&](std::uint32_t i, std::uint32_t j, const std::int32_t*, double d) {
            const std::size_t k = bin_of(d, edges_);
            const std::size_t a = kind_of[i];
            const std::size_t b = kind_of[j];
            ++counts[(a * n_kinds + b) * bins + k];
            ++counts[(b * n_kinds + a) * bins + k];
        });

    // Nothing can fail from here on.
    const double volume = std::abs(box.determinant());
    std::vector<double> shell(bins);
    for (std::size_t k = 0; k < bins; ++k) {
        const double lo = edges_[k];
        const double hi = edges_[k + 1];
        shell[k] = 4.0 / 3.0 * EIGEN_PI * (hi * hi * hi - lo * lo * lo);
    }
    const double n = double(n_atoms);
    std::vector<double> total(bins, 0.0);
    for (std::size_t a = 0; a < n_kinds; ++a) {
        for (std::size_t b = 0; b < n_kinds; ++b) {
            Sums& sums = partials_[{kinds[a], kinds[b]}];
            if (sums.g.empty()) {
                sums.g.assign(bins, 0.0);
                sums.n.assign(bins, 0.0);
            }
            const std::uint64_t* c = counts.data() + (a * n_kinds + b) * bins;
            double running = 0;
            for (std::size_t k = 0; k < bins; ++k) {
                const double count = double(c[k]);
                total[k] += count;
                sums.g[k] += count * volume / (members[a] * members[b] * shell[k]);
                running += count;
                sums.n[k] += running / members[a];
            }
            ++sums.frames;
        }
    }
    double running = 0;
    for (std::size_t k = 0; k < bins; ++k) {
        total_.g[k] += total[k] * volume / (n * n * shell[k]);
        running += total[k];
        total_.n[k] += running / n;
    }
    ++total_.frames;
    ++frames_;
}

std::vector<std::int32_t> Rdf::species() const {
    std::set<std::int32_t> seen;
    for (const auto& entry : partials_) {
        seen.insert(entry.first.first);
    }
    return {seen.begin(), seen.end()};
}

RdfCurve Rdf::curve(const Sums& sums) const {
    RdfCurve out;
    const std::size_t bins = options_.bins;
    out.r.resize(bins);
    out.g.resize(bins);
    out.n.resize(bins);
    const double frames = double(sums.frames);
    for (std::size_t k = 0; k < bins; ++k) {
        out.r[k] = 0.5 * (edges_[k] + edges_[k + 1]);
        out.g[k] = sums.g[k] / frames;
        out.n[k] = sums.n[k] / frames;
    }
    return out;
}

RdfCurve Rdf::total() const {
    if (frames_ == 0) {
        detail::fail<InvalidArgument>("Rdf::total: no frame was added");
    }
    return curve(total_);
}

RdfCurve Rdf::partial(std::int32_t a, std::int32_t b) const {
    const std::vector<std::int32_t> seen = species();
    for (const std::int32_t s : {a, b}) {
        if (!std::binary_search(seen.begin(), seen.end(), s)) {
            std::string list;
            for (const std::int32_t t : seen) {
                list += (list.empty() ? "" : ", ") + std::to_string(t);
            }
            detail::fail<InvalidArgument>(
                "Rdf::partial: species ", s, " never occurred (",
                seen.empty() ? std::string("no frame was added") : "species seen: " + list, ")");
        }
    }
    const auto found = partials_.find({a, b});
    if (found == partials_.end()) {
        detail::fail<InvalidArgument>("Rdf::partial: species ", a, " and ", b,
                                      " never occurred in the same frame");
    }
    return curve(found->second);
}

} // namespace tricell
