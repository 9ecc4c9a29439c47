// Rdf against a brute-force histogram over every image (random triclinic frames, rmax below and
// beyond the cell, several species, several frames of different cells and sizes), exact
// coordination shells of FCC, invariance under backend and threads, and every refusal.
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include <tricell/analysis/rdf.hpp>
#include <tricell/error.hpp>

#include "support/analysis_oracles.hpp"
#include "support/expect_throw_msg.hpp"
#include "support/random_systems.hpp"

namespace {

using tricell::Box;
using tricell::InvalidArgument;
using tricell::Periodicity;
using tricell::Rdf;
using tricell::RdfOptions;
using tricell::testing::brute_force_rdf_counts;

constexpr double pi = 3.14159265358979323846;

struct Frame {
    Box box;
    std::vector<Eigen::Vector3d> x;
    std::vector<std::int32_t> species;
};

Frame random_frame(std::uint64_t seed) {
    tricell::testing::RandomSystem sys = tricell::testing::random_system(seed);
    if (sys.positions.empty()) {
        sys.positions.push_back(sys.h * Eigen::Vector3d(0.3, 0.6, 0.2));
    }
    std::mt19937_64 rng(seed);
    std::vector<std::int32_t> species(sys.positions.size());
    const std::int32_t kinds[] = {0, 3, 7};
    for (auto& s : species) {
        s = kinds[rng() % 3];
    }
    return Frame{Box::from_columns(sys.h, Periodicity::all()), sys.positions, species};
}

double shell_volume(const std::vector<double>& edges, std::size_t k) {
    return 4.0 / 3.0 * pi * (std::pow(edges[k + 1], 3) - std::pow(edges[k], 3));
}

void expect_near_rel(const std::vector<double>& got, const std::vector<double>& want,
                     const char* what) {
    ASSERT_EQ(got.size(), want.size()) << what;
    for (std::size_t k = 0; k < got.size(); ++k) {
        EXPECT_NEAR(got[k], want[k], 1e-12 * (1 + std::abs(want[k]))) << what << " bin " << k;
    }
}

TEST(Rdf, MatchesBruteForceHistogram_RandomFrames) {
    for (std::uint64_t seed = 1; seed <= 90; ++seed) {
        SCOPED_TRACE(seed);
        std::mt19937_64 rng(seed);
        // Two or three frames of the same kind: different cells, atom counts and species mixes.
        std::vector<Frame> frames;
        double min_width = HUGE_VAL;
        for (std::uint64_t f = 0; f < 2 + seed % 2; ++f) {
            frames.push_back(random_frame(seed + 6 * f));
            min_width = std::min(min_width, frames.back().box.perpendicular_widths().minCoeff());
        }
        // rmax past the cell, several cells for tiny ones, capped so the oracle stays quick.
        const bool tiny = seed % 6 == 2;
        RdfOptions options;
        options.rmax =
            std::min(tricell::testing::random_system(seed).cutoff, (tiny ? 4.0 : 1.2) * min_width);
        options.bins = 1 + rng() % 40;
        Rdf rdf(options);
        for (const Frame& frame : frames) {
            rdf.add_frame(frame.box, frame.x, frame.species);
        }
        ASSERT_EQ(rdf.frames(), frames.size());
        const std::vector<double>& edges = rdf.edges();
        ASSERT_EQ(edges.size(), options.bins + 1);
        EXPECT_EQ(edges.front(), 0.0);
        EXPECT_EQ(edges.back(), options.rmax);

        // The expected averages, from the brute-force counts of each frame.
        const std::size_t bins = options.bins;
        std::vector<double> g_total(bins, 0.0), n_total(bins, 0.0);
        std::map<std::pair<int, int>, std::vector<double>> g_part, n_part;
        std::map<std::pair<int, int>, int> frames_of;
        for (const Frame& frame : frames) {
            const auto counts = brute_force_rdf_counts(frame.box, frame.x, frame.species, edges);
            const double volume = std::abs(frame.box.matrix().determinant());
            const double n = double(frame.x.size());
            std::map<int, double> members;
            for (const auto s : frame.species) {
                members[s] += 1;
            }
            std::vector<double> total(bins, 0.0);
            for (const auto& [a, na] : members) {
                for (const auto& [b, nb] : members) {
                    auto& g = g_part[{a, b}];
                    auto& running = n_part[{a, b}];
                    g.resize(bins, 0.0);
                    running.resize(bins, 0.0);
                    ++frames_of[{a, b}];
                    const auto found = counts.find({a, b});
                    double sum = 0;
                    for (std::size_t k = 0; k < bins; ++k) {
                        const double c = found == counts.end() ? 0.0 : found->second[k];
                        total[k] += c;
                        g[k] += c * volume / (na * nb * shell_volume(edges, k));
                        sum += c;
                        running[k] += sum / na;
                    }
                }
            }
            double sum = 0;
            for (std::size_t k = 0; k < bins; ++k) {
                g_total[k] += total[k] * volume / (n * n * shell_volume(edges, k));
                sum += total[k];
                n_total[k] += sum / n;
            }
        }
        for (std::size_t k = 0; k < bins; ++k) {
            g_total[k] /= double(frames.size());
            n_total[k] /= double(frames.size());
        }
        const tricell::RdfCurve total = rdf.total();
        expect_near_rel(total.g, g_total, "total g");
        expect_near_rel(total.n, n_total, "total n");
        for (std::size_t k = 0; k < bins; ++k) {
            EXPECT_DOUBLE_EQ(total.r[k], 0.5 * (edges[k] + edges[k + 1]));
        }
        for (auto& [key, g] : g_part) {
            SCOPED_TRACE(key.first * 100 + key.second);
            const double f = frames_of[key];
            std::vector<double> n = n_part[key];
            for (std::size_t k = 0; k < bins; ++k) {
                g[k] /= f;
                n[k] /= f;
            }
            const tricell::RdfCurve partial = rdf.partial(key.first, key.second);
            expect_near_rel(partial.g, g, "partial g");
            expect_near_rel(partial.n, n, "partial n");
        }
    }
}

TEST(Rdf, FccCoordinationShellsPastTheCell) {
    // Conventional FCC cell (4 atoms, a = 1) with rmax 1.5 > the cell: shells of 12 at
    // 1/sqrt 2, 6 at 1, 24 at sqrt 1.5, so n = 12, 18, 42 just past each.
    const std::vector<Eigen::Vector3d> x = {{0, 0, 0}, {0.5, 0.5, 0}, {0.5, 0, 0.5}, {0, 0.5, 0.5}};
    RdfOptions options;
    options.rmax = 1.5;
    options.bins = 150;
    Rdf rdf(options);
    rdf.add_frame(Box::from_columns(Eigen::Matrix3d::Identity()), x);
    const tricell::RdfCurve curve = rdf.total();
    const auto n_at = [&](double r) { // n at the upper edge of the bin holding r
        return curve.n[std::size_t(r / 0.01)];
    };
    EXPECT_EQ(n_at(0.69), 0.0); // upper edge 0.70 < 1/sqrt 2
    EXPECT_EQ(n_at(0.71), 12.0);
    EXPECT_EQ(n_at(0.995), 12.0);
    EXPECT_EQ(n_at(1.005), 18.0);
    EXPECT_EQ(n_at(1.23), 42.0);
    EXPECT_EQ(rdf.species(), (std::vector<std::int32_t>{0}));
}

TEST(Rdf, SameResultWithEveryBackendAndThreads) {
    for (std::uint64_t seed = 200; seed < 230; ++seed) {
        SCOPED_TRACE(seed);
        const Frame frame = random_frame(seed);
        RdfOptions options;
        options.rmax = std::min(tricell::testing::random_system(seed).cutoff,
                                1.5 * frame.box.perpendicular_widths().minCoeff());
        options.bins = 17;
        Rdf reference(options);
        reference.add_frame(frame.box, frame.x, frame.species);
        for (const auto backend : tricell::search_backends()) {
            for (const int threads : {1, 3}) {
                RdfOptions other = options;
                other.backend = backend;
                other.threads = threads;
                Rdf rdf(other);
                rdf.add_frame(frame.box, frame.x, frame.species);
                EXPECT_EQ(rdf.total().g, reference.total().g) << tricell::backend_name(backend);
                EXPECT_EQ(rdf.total().n, reference.total().n);
                for (const std::int32_t a : reference.species()) {
                    for (const std::int32_t b : reference.species()) {
                        EXPECT_EQ(rdf.partial(a, b).g, reference.partial(a, b).g);
                        EXPECT_EQ(rdf.partial(a, b).n, reference.partial(a, b).n);
                    }
                }
            }
        }
    }
}

TEST(Rdf, RefusesBadOptionsAndFramesWithoutChangingAnything) {
    RdfOptions options;
    EXPECT_THROW_MSG(Rdf{options}, InvalidArgument,
                     "RdfOptions::rmax must be finite and > 0 (got 0)");
    options.rmax = std::nan("");
    EXPECT_THROW_MSG(Rdf{options}, InvalidArgument, "rmax must be finite and > 0 (got nan)");
    options.rmax = 2;
    EXPECT_THROW_MSG(Rdf{options}, InvalidArgument,
                     "RdfOptions::bins must be between 1 and 100000000 (got 0)");
    options.bins = RdfOptions::max_bins + 1;
    EXPECT_THROW_MSG(Rdf{options}, InvalidArgument, "(got 100000001)");
    options.bins = 10;
    options.threads = -1;
    EXPECT_THROW_MSG(Rdf{options}, InvalidArgument, "RdfOptions::threads must be >= 0 (got -1)");
    options.threads = 1;

    Rdf rdf(options);
    EXPECT_THROW_MSG(rdf.total(), InvalidArgument, "Rdf::total: no frame was added");
    EXPECT_THROW_MSG(rdf.partial(0, 0), InvalidArgument,
                     "species 0 never occurred (no frame was added)");
    const std::vector<Eigen::Vector3d> x = {{0, 0, 0}, {1, 1, 1}};
    const Box open =
        Box::from_columns(4 * Eigen::Matrix3d::Identity(), Periodicity{{{true, true, false}}});
    EXPECT_THROW_MSG(rdf.add_frame(open, x), InvalidArgument,
                     "Rdf: axis c of the frame is not periodic");
    const Box box = Box::from_columns(4 * Eigen::Matrix3d::Identity());
    EXPECT_THROW_MSG(rdf.add_frame(box, std::vector<Eigen::Vector3d>{}), InvalidArgument,
                     "Rdf: the frame has no atoms");
    EXPECT_THROW_MSG(rdf.add_frame(box, x, {1}), InvalidArgument,
                     "Rdf: species has 1 entries for 2 positions");
    EXPECT_THROW_MSG(rdf.add_frame(box, x, {1, -2}), InvalidArgument,
                     "Rdf: species of atom 1 must be >= 0 (got -2)");
    const std::vector<Eigen::Vector3d> bad = {{0, 0, 0}, {std::nan(""), 1, 1}};
    EXPECT_THROW_MSG(rdf.add_frame(box, bad), InvalidArgument, "position 1 is not finite");
    EXPECT_EQ(rdf.frames(), 0u);

    rdf.add_frame(box, x, {1, 1});
    rdf.add_frame(box, x, {2, 2});
    EXPECT_EQ(rdf.frames(), 2u);
    EXPECT_EQ(rdf.species(), (std::vector<std::int32_t>{1, 2}));
    EXPECT_THROW_MSG(rdf.partial(1, 5), InvalidArgument,
                     "Rdf::partial: species 5 never occurred (species seen: 1, 2)");
    EXPECT_THROW_MSG(rdf.partial(1, 2), InvalidArgument,
                     "species 1 and 2 never occurred in the same frame");
    EXPECT_NO_THROW(rdf.partial(2, 2));
}

} // namespace
