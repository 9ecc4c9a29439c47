// direct_probe: a measured prototype of a small-system path for the neighbour search, by
// direct image enumeration, against tricell's grid search on the same structure (issue 13).
//
// For a cell smaller than the cutoff the grid has one cell per axis and a stencil of hundreds of
// offsets; every offset is a separate image, so the grid search scans ranges of N atoms, one
// range per (image, atom), and pays its loop and call overhead per range. The direct path turns
// the loops around: the images T = H S that can hold a pair (|T| < cutoff + the largest distance
// between two wrapped atoms) are listed once, struct-of-arrays, and for every atom pair (a, b)
// one contiguous loop over the images computes D = x_b - (x_a - T) (the grid's arithmetic, term
// for term, so d and D have the grid's bits) and keeps |D| < cutoff with a branch-free
// compaction. Half lists take a < b over all images and a == b over the positive half of them,
// already in the canonical orientation. Nothing is allocated once the buffers have grown.
//
// The probe checks that the direct path finds exactly the grid's (i, j, S) and, for full lists,
// the same d bit for bit, then times both into reused memory.
//
// usage: direct_probe FILE --cutoff R [--half] [--repeat K] [--calls C]
// prints "key value" lines: pairs, images, candidates, grid_s, direct_s (medians), same
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <tuple>
#include <vector>

#include <tricell/detail/distance_kernel.hpp>
#include <tricell/io/structure.hpp>
#include <tricell/neighbor_list.hpp>

namespace {

using Clock = std::chrono::steady_clock;

struct DirectSearch {
    // per atom: wrapped Cartesian position and the image it came from (x = wrapped + H image)
    std::vector<double> x, y, z;
    std::vector<std::int32_t> image;
    // images T = H S that can hold a pair; index 0 is S = 0; with `half`, positive S follow
    std::vector<double> tx, ty, tz;
    std::vector<std::int32_t> s;
    std::size_t positive_begin = 0; // first image with S > 0 lexicographically
    // output, reused
    std::vector<std::uint32_t> out_i, out_j;
    std::vector<std::int32_t> out_s;
    std::vector<double> out_d;
    std::size_t size = 0;

    void run(const tricell::Box& box, tricell::PointsView positions, double cutoff, bool half);

  private:
    void scan(std::uint32_t a, std::uint32_t b, std::size_t k_begin, std::size_t k_end,
              double cutoff_sq);
};

void DirectSearch::run(const tricell::Box& box, tricell::PointsView positions, double cutoff,
                       bool half) {
    const std::size_t n = positions.size();
    const Eigen::Matrix3d& h = box.matrix();
    x.resize(n);
    y.resize(n);
    z.resize(n);
    image.resize(3 * n);
    Eigen::Vector3d lo = Eigen::Vector3d::Zero(), hi = Eigen::Vector3d::Zero();
    for (std::size_t i = 0; i < n; ++i) {
        const tricell::WrappedFractional w =
            box.wrap(box.to_fractional(tricell::Cartesian(positions[i])));
        const Eigen::Vector3d img(w.image[0], w.image[1], w.image[2]);
        const Eigen::Vector3d r = Eigen::Vector3d(positions[i]) - h * img; // as the grid does
        x[i] = r.x();
        y[i] = r.y();
        z[i] = r.z();
        for (int k = 0; k < 3; ++k) {
            image[3 * i + std::size_t(k)] = w.image[k];
        }
        lo = i == 0 ? r : Eigen::Vector3d(lo.cwiseMin(r));
        hi = i == 0 ? r : Eigen::Vector3d(hi.cwiseMax(r));
    }
    // |D| >= |T| - |x_b - x_a| >= |T| - span, so images with |T| >= cutoff + span hold no pair.
    const double reach = cutoff * (1 + 1e-9) + (hi - lo).norm();
    int m[3];
    for (int k = 0; k < 3; ++k) {
        m[k] = box.periodic(k) ? int(std::ceil(reach / box.perpendicular_widths()[k])) : 0;
    }
    // Images with |T| < reach, S = 0 first, then S < 0, then S > 0 (lexicographically), so that a
    // half list scans [positive_begin, end) for a == b. Per row (sa, sb) the sc with
    // |A + sc c| < reach form an interval, from the roots of a quadratic (then checked exactly).
    tx.assign(1, 0.0);
    ty.assign(1, 0.0);
    tz.assign(1, 0.0);
    s.assign(3, 0);
    const Eigen::Vector3d c = h.col(2);
    const double cc = c.squaredNorm();
    for (int pass = 0; pass < 2; ++pass) { // pass 0: S < 0, pass 1: S > 0
        for (int sa = -m[0]; sa <= m[0]; ++sa) {
            for (int sb = -m[1]; sb <= m[1]; ++sb) {
                const Eigen::Vector3d row = h.col(0) * sa + h.col(1) * sb;
                const double ac = row.dot(c);
                const double disc = ac * ac - cc * (row.squaredNorm() - reach * reach);
                if (disc < 0) {
                    continue;
                }
                const double root = std::sqrt(disc);
                const int sc_lo = std::max(-m[2], int(std::floor((-ac - root) / cc)));
                const int sc_hi = std::min(m[2], int(std::ceil((-ac + root) / cc)));
                for (int sc = sc_lo; sc <= sc_hi; ++sc) {
                    const bool pos = sa > 0 || (sa == 0 && (sb > 0 || (sb == 0 && sc > 0)));
                    const bool zero = sa == 0 && sb == 0 && sc == 0;
                    if (zero || pos != (pass == 1)) {
                        continue;
                    }
                    const Eigen::Vector3d t = h.col(0) * sa + h.col(1) * sb + h.col(2) * sc;
                    if (t.norm() < reach) { // the grid's shift vector, term for term
                        tx.push_back(t.x());
                        ty.push_back(t.y());
                        tz.push_back(t.z());
                        s.insert(s.end(), {sa, sb, sc});
                    }
                }
            }
        }
        if (pass == 0) {
            positive_begin = tx.size();
        }
    }

    const double cutoff_sq = tricell::detail::strict_threshold_sq(cutoff);
    size = 0;
    const std::size_t images = tx.size();
    for (std::uint32_t a = 0; a < n; ++a) {
        for (std::uint32_t b = half ? a : 0; b < n; ++b) {
            if (a == b) {
                scan(a, b, half ? positive_begin : 1, images, cutoff_sq); // never (a, a, 0)
            } else {
                scan(a, b, 0, images, cutoff_sq);
            }
        }
    }
}

void DirectSearch::scan(std::uint32_t a, std::uint32_t b, std::size_t k_begin, std::size_t k_end,
                        double cutoff_sq) {
    constexpr std::size_t block = 64;
    double d_sq[block], dx[block], dy[block], dz[block];
    std::uint32_t hits[block];
    const double xa = x[a], ya = y[a], za = z[a], xb = x[b], yb = y[b], zb = z[b];
    const int base[3] = {image[3 * a] - image[3 * b], image[3 * a + 1] - image[3 * b + 1],
                         image[3 * a + 2] - image[3 * b + 2]};
    for (std::size_t start = k_begin; start < k_end; start += block) {
        const std::size_t count = std::min(block, k_end - start);
        for (std::size_t k = 0; k < count; ++k) { // vectorised: the grid's D = x_b - (x_a - T)
            dx[k] = xb - (xa - tx[start + k]);
            dy[k] = yb - (ya - ty[start + k]);
            dz[k] = zb - (za - tz[start + k]);
            d_sq[k] = dx[k] * dx[k] + dy[k] * dy[k] + dz[k] * dz[k];
        }
        std::uint32_t found = 0;
        for (std::uint32_t k = 0; k < count; ++k) { // branch-free compaction
            hits[found] = k;
            found += d_sq[k] < cutoff_sq ? 1u : 0u;
        }
        if (size + found > out_i.size()) {
            const std::size_t grown = std::max<std::size_t>(1024, 2 * (size + found));
            out_i.resize(grown);
            out_j.resize(grown);
            out_s.resize(3 * grown);
            out_d.resize(grown);
        }
        for (std::uint32_t f = 0; f < found; ++f) {
            const std::size_t k = hits[f], img = start + k;
            out_i[size] = a;
            out_j[size] = b;
            out_s[3 * size] = s[3 * img] + base[0];
            out_s[3 * size + 1] = s[3 * img + 1] + base[1];
            out_s[3 * size + 2] = s[3 * img + 2] + base[2];
            out_d[size] = std::sqrt(d_sq[k]);
            ++size;
        }
    }
}

// With fixed_calls > 0 (--calls, for instruction counts under callgrind): exactly that many
// calls per sample, one sample.
long fixed_calls = 0;

template <class Body> double median_time(Body&& body, int repeat) {
    body();
    if (fixed_calls > 0) {
        const auto start = Clock::now();
        for (long r = 0; r < fixed_calls; ++r) {
            body();
        }
        return std::chrono::duration<double>(Clock::now() - start).count() / double(fixed_calls);
    }
    long inner = 1;
    for (;;) { // enough calls per sample for at least 2 ms
        const auto start = Clock::now();
        for (long r = 0; r < inner; ++r) {
            body();
        }
        if (std::chrono::duration<double>(Clock::now() - start).count() > 2e-3 || inner > 1e6) {
            break;
        }
        inner *= 2;
    }
    std::vector<double> samples;
    for (int k = 0; k < repeat; ++k) {
        const auto start = Clock::now();
        for (long r = 0; r < inner; ++r) {
            body();
        }
        samples.push_back(std::chrono::duration<double>(Clock::now() - start).count() /
                          double(inner));
    }
    std::sort(samples.begin(), samples.end());
    return samples[samples.size() / 2];
}

using Key = std::tuple<std::uint32_t, std::uint32_t, int, int, int, double>;

} // namespace

int main(int argc, char** argv) {
    std::string file;
    double cutoff = 0;
    bool half = false;
    int repeat = 7;
    for (int a = 1; a < argc; ++a) {
        const std::string arg = argv[a];
        if (arg == "--cutoff" && a + 1 < argc) {
            cutoff = std::atof(argv[++a]);
        } else if (arg == "--repeat" && a + 1 < argc) {
            repeat = std::max(1, std::atoi(argv[++a]));
        } else if (arg == "--half") {
            half = true;
        } else if (arg == "--calls" && a + 1 < argc) {
            fixed_calls = std::max(1, std::atoi(argv[++a]));
        } else if (file.empty() && arg[0] != '-') {
            file = arg;
        } else {
            file.clear();
            break;
        }
    }
    if (file.empty() || !(cutoff > 0)) {
        std::fprintf(stderr,
                     "usage: direct_probe FILE --cutoff R [--half] [--repeat K] [--calls C]\n");
        return 2;
    }
    tricell::io::Structure structure;
    try {
        structure = tricell::io::read_structure(file);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "direct_probe: %s\n", e.what());
        return 1;
    }
    tricell::NeighborOptions options;
    options.cutoff = cutoff;
    options.half = half;
    tricell::NeighborList list;
    DirectSearch direct;
    const double grid_s = median_time(
        [&] { tricell::compute_neighbors(structure.box, structure.positions, options, list); },
        repeat);
    const double direct_s =
        median_time([&] { direct.run(structure.box, structure.positions, cutoff, half); }, repeat);

    // Same (i, j, S) as the grid, and for full lists the same d to the bit.
    std::vector<Key> grid_keys, direct_keys;
    for (std::size_t k = 0; k < list.size(); ++k) {
        grid_keys.emplace_back(list.i()[k], list.j()[k], list.shifts()[3 * k],
                               list.shifts()[3 * k + 1], list.shifts()[3 * k + 2],
                               half ? 0.0 : list.distances()[k]);
    }
    for (std::size_t k = 0; k < direct.size; ++k) {
        direct_keys.emplace_back(direct.out_i[k], direct.out_j[k], direct.out_s[3 * k],
                                 direct.out_s[3 * k + 1], direct.out_s[3 * k + 2],
                                 half ? 0.0 : direct.out_d[k]);
    }
    std::sort(grid_keys.begin(), grid_keys.end());
    std::sort(direct_keys.begin(), direct_keys.end());
    const std::size_t n = structure.size();
    const double candidates = half
                                  ? double(n) * (double(n) - 1) / 2 * double(direct.tx.size()) +
                                        double(n) * double(direct.tx.size() - direct.positive_begin)
                                  : double(n) * double(n) * double(direct.tx.size()) - double(n);
    std::printf("pairs %zu\n", list.size());
    std::printf("images %zu\n", direct.tx.size());
    std::printf("candidates %.0f\n", candidates);
    std::printf("grid_s %.6g\n", grid_s);
    std::printf("direct_s %.6g\n", direct_s);
    std::printf("same %d\n", grid_keys == direct_keys ? 1 : 0);
    return grid_keys == direct_keys ? 0 : 1;
}
