// The compact hash backend (Ihmsen et al. 2011, "A parallel SPH implementation on multi-core
// CPUs"): the same fractional cells as the dense grid at the full resolution the cutoff asks for,
// with no cap, but only the non-empty cells are stored, so memory is O(N) whatever the volume (a
// droplet in a huge box, two clusters far apart along open axes). The atoms are sorted by cell (a,
// b, c lexicographic, c fastest), so a cell's atoms are contiguous and the non-empty cells of one
// stencil row are consecutive. A table of about 2 N slots maps a cell's integer coordinates (hash:
// coordinates times large primes, XOR, modulo the table size) to the non-empty cells stored in that
// slot; each is checked against its own coordinates, so a collision costs a comparison and never a
// miss or a duplicate. A neighbour cell is found from the integer coordinates plus a stencil
// offset, wrapped along periodic axes (the wrap gives the image shift, as in the dense grid);
// consecutive cells of a row found next to each other in the sorted order are scanned as one range.
// The work units are the non-empty cells.
#include <algorithm>
#include <limits>
#include <numeric>

#include "backends/backend.hpp"
#include "backends/grid_neighbourhood.hpp"

namespace tricell::detail {

namespace {

class HashBackend final : public Backend {
  public:
    void bin(const BinningInput& input, std::vector<std::uint32_t>& order) override {
        const std::size_t n = input.fractional.size();
        // No cap beyond what keeps the flat key representable (grid.hpp's per-axis limit).
        cells_.build(input, std::numeric_limits<std::size_t>::max() / 2, false);
        const CellGrid& grid = cells_.grid();
        std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed(n);
        for (std::size_t i = 0; i < n; ++i) {
            keyed[i] = {std::uint64_t(grid.cell_of(input.fractional[i])), std::uint32_t(i)};
        }
        std::sort(keyed.begin(), keyed.end());
        order.resize(n);
        cell_.clear();
        start_.clear();
        for (std::size_t k = 0; k < n; ++k) {
            order[k] = keyed[k].second;
            if (k == 0 || keyed[k].first != keyed[k - 1].first) {
                const std::size_t flat = std::size_t(keyed[k].first);
                const std::array<int, 3> c = cells_.coordinates(flat);
                cell_.push_back(c);
                start_.push_back(std::uint32_t(k));
            }
        }
        start_.push_back(std::uint32_t(n));

        // The table: slot s holds the cells slot_cells_[slot_start_[s] .. slot_start_[s + 1]).
        const std::size_t cells = cell_.size();
        const std::size_t slots = input.options.hash_table_size != 0
                                      ? input.options.hash_table_size
                                      : std::max<std::size_t>(1, 2 * n);
        slot_start_.assign(slots + 1, 0);
        std::vector<std::uint32_t> slot_of(cells);
        for (std::size_t e = 0; e < cells; ++e) {
            slot_of[e] = std::uint32_t(slot(cell_[e][0], cell_[e][1], cell_[e][2], slots));
            ++slot_start_[slot_of[e] + 1];
        }
        std::partial_sum(slot_start_.begin(), slot_start_.end(), slot_start_.begin());
        slot_cells_.resize(cells);
        std::vector<std::uint32_t> cursor(slot_start_.begin(), slot_start_.end() - 1);
        for (std::size_t e = 0; e < cells; ++e) {
            slot_cells_[cursor[slot_of[e]]++] = std::uint32_t(e);
        }
    }

    std::size_t unit_count() const override { return cell_.size(); }

    void occupancy(UnitOccupancy& out) const override {
        out.atoms.resize(cell_.size());
        for (std::size_t e = 0; e < cell_.size(); ++e) {
            out.atoms[e] = double(start_[e + 1] - start_[e]);
        }
        out.volume.assign(cell_.size(), cells_.cell_volume());
    }

    double neighbours() const override { return double(cells_.stencil().size()); }

    void visit(std::size_t begin, std::size_t end, CandidateScanner& scan) const override {
        const CellGrid& grid = cells_.grid();
        const std::array<int, 3>& n = grid.dims();
        const Periodicity& pbc = grid.periodicity();
        const std::size_t slots = slot_start_.size() - 1;
        for (std::size_t e1 = begin; e1 < end; ++e1) {
            const std::array<int, 3>& c = cell_[e1];
            for (const StencilRow& row : cells_.rows()) {
                int na = 0, nb = 0, sa = 0, sb = 0;
                if (!wrap(c[0] + row.da, n[0], pbc[0], na, sa) ||
                    !wrap(c[1] + row.db, n[1], pbc[1], nb, sb)) {
                    continue; // beyond the end of an open axis
                }
                const bool own_row = row.da == 0 && row.db == 0;
                // Consecutive cells of the row, within one image along c, that are consecutive in
                // the sorted order merge into one range [run_first, run_last].
                std::size_t run_first = 0, run_last = 0;
                int run_shift = 0;
                bool run = false;
                auto flush = [&] {
                    if (run) {
                        const bool own =
                            own_row && run_shift == 0 && run_first <= e1 && e1 <= run_last;
                        scan.ranges(start_[e1], start_[e1 + 1], start_[run_first],
                                    start_[run_last + 1], scan.shift(sa, sb, run_shift), own);
                        run = false;
                    }
                };
                for (int t = c[2] + row.dc_lo; t <= c[2] + row.dc_hi; ++t) {
                    int nc = 0, sc = 0;
                    if (!wrap(t, n[2], pbc[2], nc, sc)) {
                        continue;
                    }
                    const std::size_t e2 = find(na, nb, nc, slots);
                    if (e2 == missing) {
                        continue;
                    }
                    if (run && sc == run_shift && e2 == run_last + 1) {
                        run_last = e2;
                        continue;
                    }
                    flush();
                    run = true;
                    run_first = run_last = e2;
                    run_shift = sc;
                }
                flush();
            }
        }
    }

    void describe(SearchInfo& info) const override {
        info.backend = SearchBackend::hash;
        info.cells = cells_.grid().dims();
        info.stored_cells = cell_.size();
    }

  private:
    static constexpr std::size_t missing = std::numeric_limits<std::size_t>::max();

    static std::size_t slot(int a, int b, int c, std::size_t slots) {
        const std::uint64_t h = (std::uint64_t(std::uint32_t(a)) * 73856093u) ^
                                (std::uint64_t(std::uint32_t(b)) * 19349663u) ^
                                (std::uint64_t(std::uint32_t(c)) * 83492791u);
        return std::size_t(h % slots);
    }

    // Cell coordinate and image shift of t along an axis of n cells; false beyond an open end.
    static bool wrap(int t, int n, bool periodic, int& cell, int& shift) {
        if (periodic) {
            shift = floor_div(t, n);
            cell = t - shift * n;
            return true;
        }
        cell = t;
        shift = 0;
        return t >= 0 && t < n;
    }

    std::size_t find(int a, int b, int c, std::size_t slots) const {
        const std::size_t s = slot(a, b, c, slots);
        for (std::uint32_t k = slot_start_[s]; k < slot_start_[s + 1]; ++k) {
            const std::array<int, 3>& cell = cell_[slot_cells_[k]];
            if (cell[0] == a && cell[1] == b && cell[2] == c) {
                return slot_cells_[k];
            }
        }
        return missing;
    }

    GridNeighbourhood cells_;
    std::vector<std::array<int, 3>> cell_; // coordinates of each non-empty cell, sorted
    std::vector<std::uint32_t> start_;     // its atoms: [start_[e], start_[e + 1])
    std::vector<std::uint32_t> slot_start_;
    std::vector<std::uint32_t> slot_cells_;
};

} // namespace

std::unique_ptr<Backend> make_hash_backend() {
    return std::make_unique<HashBackend>();
}

} // namespace tricell::detail
