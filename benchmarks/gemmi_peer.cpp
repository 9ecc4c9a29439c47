// gemmi_peer: times gemmi's NeighborSearch (the Debian gemmi-dev headers) on a structure file,
// as the peer in benchmarks/compare. It visits every atom's neighbours within the cutoff and
// counts them, storing nothing (gemmi's own visitor, for_each). The structure is read with
// tricell::io so that both tools see identical positions.
//
// usage: gemmi_peer FILE CUTOFF [REPEAT]
// prints: pairs=<full-list pairs> median_s=<seconds> min_s=<seconds>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include <gemmi/neighbor.hpp>
#include <gemmi/small.hpp>

#include <tricell/io/structure.hpp>

int main(int argc, char** argv) {
    if (argc < 3) {
        std::fprintf(stderr, "usage: gemmi_peer FILE CUTOFF [REPEAT]\n");
        return 2;
    }
    const double cutoff = std::atof(argv[2]);
    const int repeat = argc > 3 ? std::atoi(argv[3]) : 5;
    tricell::io::Structure structure;
    try {
        structure = tricell::io::read_structure(argv[1]);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "gemmi_peer: %s\n", e.what());
        return 1;
    }
    const tricell::LatticeParameters p = structure.box.parameters();
    gemmi::SmallStructure small;
    small.cell.set(p.a, p.b, p.c, p.alpha, p.beta, p.gamma);
    for (const Eigen::Vector3d& r : structure.positions) {
        const Eigen::Vector3d s = structure.box.to_fractional(tricell::Cartesian(r));
        gemmi::SmallStructure::Site site;
        site.fract = gemmi::Fractional(s.x(), s.y(), s.z());
        site.element = gemmi::El::Si;
        small.sites.push_back(site);
    }

    std::vector<double> seconds;
    long long pairs = 0;
    for (int run = 0; run <= repeat; ++run) { // run 0 is the warm-up
        const auto start = std::chrono::steady_clock::now();
        gemmi::NeighborSearch ns(small, cutoff);
        ns.populate();
        long long count = 0;
        double sum = 0;
        for (const gemmi::SmallStructure::Site& site : small.sites) {
            const gemmi::Position pos = small.cell.orthogonalize(site.fract);
            ns.for_each(pos, '\0', float(cutoff), [&](gemmi::NeighborSearch::Mark&, float d_sq) {
                ++count;
                sum += d_sq;
            });
        }
        const auto stop = std::chrono::steady_clock::now();
        pairs = count - static_cast<long long>(small.sites.size()); // each atom meets itself
        if (run > 0) {
            seconds.push_back(std::chrono::duration<double>(stop - start).count());
        }
        if (sum < 0) {
            std::printf("impossible\n");
        }
    }
    std::sort(seconds.begin(), seconds.end());
    std::printf("pairs=%lld median_s=%.6g min_s=%.6g\n", pairs, seconds[seconds.size() / 2],
                seconds.front());
    return 0;
}
