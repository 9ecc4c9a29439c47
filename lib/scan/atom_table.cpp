#include "scan/atom_table.hpp"

#include <algorithm>

#include "detail/parallel.hpp"

namespace tricell::detail {

namespace {

// The table gathers each atom from the caller's order by the backend's (for a system much larger
// than the caches, a miss on nearly every atom), so it asks for the atom this many ahead first.
constexpr std::size_t gather_ahead = 16;

inline void prefetch(const void* address) {
#if defined(__GNUC__) || defined(__clang__)
    __builtin_prefetch(address);
#else
    (void)address;
#endif
}

} // namespace

void fill_atom_table(const Eigen::Matrix3d& h, PointsView positions,
                     const WrappedPositions& wrapped, std::vector<std::uint32_t>& order,
                     const std::vector<std::uint8_t>& query, std::size_t threads,
                     AtomTable& atoms) {
    const std::size_t n = positions.size();
    const PairArray<std::int32_t>& image = wrapped.image;
    atoms.x.resize(n);
    atoms.y.resize(n);
    atoms.z.resize(n);
    atoms.image.resize(3 * n);
    atoms.index.swap(order);
    parallel_ranges(n, threads, [&](std::size_t begin, std::size_t end, std::size_t) {
        for (std::size_t k = begin; k < end; ++k) {
            if (k + gather_ahead < end) {
                const std::size_t ahead = atoms.index[k + gather_ahead];
                prefetch(positions.data + 3 * ahead); // an atom may span two cache lines
                prefetch(positions.data + 3 * ahead + 2);
                prefetch(image.data() + 3 * ahead);
                prefetch(image.data() + 3 * ahead + 2);
            }
            const std::size_t i = atoms.index[k];
            const Eigen::Vector3d img(image[3 * i], image[3 * i + 1], image[3 * i + 2]);
            const Eigen::Vector3d r = Eigen::Vector3d(positions[i]) - h * img;
            atoms.x[k] = r.x();
            atoms.y[k] = r.y();
            atoms.z[k] = r.z();
            for (std::size_t a = 0; a < 3; ++a) {
                atoms.image[3 * k + a] = image[3 * i + a];
            }
        }
    });
    atoms.zero_images = std::all_of(image.data(), image.data() + image.size(),
                                    [](std::int32_t v) { return v == 0; });
    atoms.query.resize(query.empty() ? 0 : n);
    for (std::size_t k = 0; k < atoms.query.size(); ++k) {
        atoms.query[k] = query[atoms.index[k]];
    }
}

} // namespace tricell::detail
