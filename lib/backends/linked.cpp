// The linked backend: the same capped grid and stencil as the dense one, with the atoms left in
// the caller's order and chained per cell (LinkedCellList, head/next). Each cell is paired with
// each stencil offset, one chain against another. It needs no reordering and two small arrays,
// but walking a chain jumps around memory (benchmarks/ compares it with the dense backend). The
// work units are cells.
#include "backends/backend.hpp"
#include "backends/grid_neighbourhood.hpp"
#include "tricell/cell_list.hpp"

namespace tricell::detail {

namespace {

class LinkedBackend final : public Backend {
  public:
    void bin(const BinningInput& input, std::vector<std::uint32_t>& order) override {
        const std::size_t n = input.fractional.size();
        cells_.build(input, input.plan.cell_cap, true);
        std::vector<std::uint32_t> cell_of(n);
        order.resize(n);
        for (std::size_t i = 0; i < n; ++i) {
            cell_of[i] = static_cast<std::uint32_t>(cells_.grid().cell_of(input.fractional[i]));
            order[i] = std::uint32_t(i);
        }
        linked_.build(cell_of, cells_.grid().cell_count());
        half_ = input.plan.half_stencil(input.options);
    }

    std::size_t unit_count() const override { return cells_.grid().cell_count(); }

    void occupancy(UnitOccupancy& out) const override {
        out.atoms.assign(unit_count(), 0.0);
        for (std::size_t c = 0; c < out.atoms.size(); ++c) {
            for (auto a = linked_.head(c); a != LinkedCellList::end; a = linked_.next(a)) {
                out.atoms[c] += 1;
            }
        }
        out.volume.assign(unit_count(), cells_.cell_volume());
    }

    double neighbours() const override { return double(cells_.stencil().size()); }

    void visit(std::size_t begin, std::size_t end, CandidateScanner& scan) const override {
        for (std::size_t c1 = begin; c1 < end; ++c1) {
            if (linked_.head(c1) == LinkedCellList::end) {
                continue;
            }
            const std::array<int, 3> c = cells_.coordinates(c1);
            for (const CellOffset& d : cells_.stencil().offsets()) {
                const int na = cells_.neighbour_cell(0, c[0] + d[0]);
                const int nb = cells_.neighbour_cell(1, c[1] + d[1]);
                const int nc = cells_.neighbour_cell(2, c[2] + d[2]);
                if (na < 0 || nb < 0 || nc < 0) {
                    continue; // beyond the end of an open axis
                }
                const std::int32_t head2 = linked_.head(cells_.grid().flat(na, nb, nc));
                if (head2 == LinkedCellList::end) {
                    continue;
                }
                const ImageShift s = scan.shift(cells_.neighbour_shift(0, c[0] + d[0]),
                                                cells_.neighbour_shift(1, c[1] + d[1]),
                                                cells_.neighbour_shift(2, c[2] + d[2]));
                const bool own = d[0] == 0 && d[1] == 0 && d[2] == 0;
                for (std::int32_t a = linked_.head(c1); a != LinkedCellList::end;
                     a = linked_.next(std::size_t(a))) {
                    if (!scan.wants(std::uint32_t(a))) {
                        continue;
                    }
                    const std::int32_t first =
                        (own && half_) ? linked_.next(std::size_t(a)) : head2;
                    for (std::int32_t b = first; b != LinkedCellList::end;
                         b = linked_.next(std::size_t(b))) {
                        if (!(own && b == a)) {
                            scan.pair(std::uint32_t(a), std::uint32_t(b), s);
                        }
                    }
                }
            }
        }
    }

    void describe(SearchInfo& info) const override {
        info.backend = SearchBackend::linked;
        info.cells = cells_.grid().dims();
        info.stored_cells = cells_.grid().cell_count();
    }

  private:
    GridNeighbourhood cells_;
    LinkedCellList linked_;
    bool half_ = false;
};

} // namespace

std::unique_ptr<Backend> make_linked_backend() {
    return std::make_unique<LinkedBackend>();
}

} // namespace tricell::detail
