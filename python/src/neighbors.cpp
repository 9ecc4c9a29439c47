// tricell.NeighborList and tricell.VerletList: the C++ searches behind a numpy interface.
//
// NeighborList keeps one NeighborSearch (grid, cell list, stencil buffers) and a small pool of
// output lists between calls. compute() with copy=False hands out views of a pooled list's
// arrays; their base object holds a reference to that list, so a view stays valid for as long
// as it exists, even after the NeighborList object is gone. The next compute() writes into a
// pooled list that no view refers to (allocating one only when every pooled list is still
// viewed), so a view never changes under the caller and a loop that drops its previous
// results reuses the same memory call after call. The GIL is released during every search; a
// mutex serialises calls on one object from several Python threads.
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <tricell/batch.hpp>
#include <tricell/error.hpp>
#include <tricell/neighbor_list.hpp>
#include <tricell/verlet.hpp>

#include "arguments.hpp"
#include "batch_layout.hpp"
#include "columns.hpp"

namespace tricell::python {

namespace {

// `value` as a sequence (a list, a tuple, an array of one more dimension), else ValueError.
py::sequence checked_sequence(const py::handle& value, const char* name) {
    if (!py::isinstance<py::sequence>(value) || py::isinstance<py::str>(value)) {
        throw py::value_error(std::string(name) +
                              " must be a sequence with one entry per "
                              "structure (got " +
                              described(value) + ")");
    }
    return py::reinterpret_borrow<py::sequence>(value);
}

class PyNeighborList {
  public:
    // cutoff: a float (one cutoff), a dict {(species a, species b): cutoff} (a per-species-pair
    // table; compute() then needs species=) or None (compute() then needs radii=).
    PyNeighborList(const py::object& cutoff, bool full, bool sorted, int threads,
                   const std::string& backend, std::size_t max_pairs, bool grouped,
                   const py::object& max_bytes, std::size_t max_neighbors, double tie_tolerance,
                   bool symmetric) {
        set_cutoff(cutoff, options_);
        per_atom_radii_ = cutoff.is_none();
        options_.half = !full;
        options_.sorted = sorted;
        options_.grouped = grouped;
        options_.threads = threads;
        options_.backend = parse_backend(backend);
        options_.max_pairs = max_pairs;
        options_.max_bytes = max_bytes_argument(max_bytes);
        options_.max_neighbors = max_neighbors;
        options_.tie_tolerance = tie_tolerance;
        options_.symmetric = symmetric;
        // The library's own rule, in this constructor's argument names.
        if (max_neighbors != 0 && !full) {
            throw py::value_error("max_neighbors keeps the nearest pairs of each centre of a full "
                                  "list: full must be True (got full=False)");
        }
        if (max_neighbors != 0 && sorted) {
            throw py::value_error("max_neighbors orders each centre's pairs nearest first, by "
                                  "(d, j, S): sorted=True (by j, S) cannot be asked with it");
        }
        if (!per_atom_radii_) {
            options_.validate();
        }
    }

    py::object compute(const py::handle& points, const py::handle& box, const py::handle& periodic,
                       const std::string& quantities, bool copy, const py::handle& radii,
                       const py::handle& species, const py::handle& query) {
        const DoubleArray x = points_array(points);
        const Box search_box = box_from_rows(box, periodic);
        NeighborOptions options = options_;
        const QuantitySpec spec = parse_quantities(quantities);
        options.quantities = spec.stored;
        require_offsets_if_asked(spec);
        const auto n = static_cast<std::size_t>(x.shape(0));
        const PointsView view(x.data(), n);
        if (per_atom_radii_ == radii.is_none()) {
            throw py::value_error(per_atom_radii_
                                      ? "radii= is needed: this NeighborList was made with "
                                        "cutoff=None (per-atom radii)"
                                      : "radii= is only for a NeighborList made with cutoff=None");
        }
        if (options.species_cutoffs.empty() != species.is_none()) {
            throw py::value_error(species.is_none()
                                      ? "species= is needed: this NeighborList was made with a "
                                        "cutoff dict of species pairs"
                                      : "species= is only for a NeighborList made with a cutoff "
                                        "dict of species pairs");
        }
        if (!radii.is_none()) {
            const DoubleArray r = per_atom_array(radii, n, "radii");
            options.radii.assign(r.data(), r.data() + n);
        }
        if (!species.is_none()) {
            options.species = per_atom_species(species, n);
        }
        if (!query.is_none()) {
            // The search checks each index against the points (naming query[k]).
            const std::vector<std::int32_t> q = species_array(query, "query");
            std::vector<std::uint32_t> indices(q.size());
            for (std::size_t k = 0; k < q.size(); ++k) {
                if (q[k] < 0) {
                    throw py::value_error("query[" + std::to_string(k) + "] is " +
                                          std::to_string(q[k]) + ", not the index of one of the " +
                                          std::to_string(n) + " positions");
                }
                indices[k] = std::uint32_t(q[k]);
            }
            options.query = std::move(indices);
        }

        std::shared_ptr<NeighborList> list;
        {
            py::gil_scoped_release release;
            std::lock_guard<std::mutex> lock(mutex_);
            list = free_entry(pool_);
            search_.build(search_box, view, options);
            search_.compute(*list);
        }
        return pair_columns(*list, spec, copy ? nullptr : list);
    }

    // One list per structure of a batch (compute_neighbors_batch), the NeighborList's options
    // for all; the inputs are converted (and checked, each naming its structure) with the GIL
    // held, the search runs without it. Without batch_ptr the structures come as sequences of
    // arrays; with it as the concatenated format (points N_total x 3, boxes B x 3 x 3), and i
    // and j index the concatenated points.
    py::tuple compute_batch(const py::handle& points, const py::handle& boxes,
                            const py::handle& periodic, const std::string& quantities,
                            const py::handle& batch_ptr, bool copy) {
        if (per_atom_radii_ || !options_.species_cutoffs.empty()) {
            throw py::value_error("compute_batch needs a NeighborList made with one float cutoff");
        }
        NeighborOptions options = options_;
        const QuantitySpec spec = parse_quantities(quantities);
        options.quantities = spec.stored;
        require_offsets_if_asked(spec);
        std::vector<DoubleArray> arrays;
        std::vector<BatchStructure> structures;
        std::vector<std::int64_t> ptr;
        if (batch_ptr.is_none()) {
            structures = listed_structures(points, boxes, periodic, arrays);
        } else {
            arrays.push_back(points_array(points));
            ptr = batch_pointer(batch_ptr, std::size_t(arrays[0].shape(0)));
            structures = concatenated_structures(arrays[0], ptr, boxes, periodic);
        }
        std::shared_ptr<BatchList> batch;
        try {
            py::gil_scoped_release release;
            std::lock_guard<std::mutex> lock(mutex_);
            batch = free_entry(batch_pool_);
            recycler_->lend(*batch);
            compute_neighbors_batch(structures, options, *batch,
                                    ptr.empty() ? BatchIndices::local : BatchIndices::global);
        } catch (const PairLimitError&) {
            throw;
        } catch (const Error& e) {
            if (ptr.empty()) {
                throw;
            }
            throw py::value_error(with_rows_of(e.what(), ptr.data(), ptr.size(), "points"));
        }
        return batch_columns(*batch, spec, copy ? nullptr : batch, recycler_);
    }

    bool full() const { return !options_.half; }
    bool sorted() const { return options_.sorted; }
    bool grouped() const { return options_.grouped; }
    std::size_t max_neighbors() const { return options_.max_neighbors; }
    double tie_tolerance() const { return options_.tie_tolerance; }
    bool symmetric() const { return options_.symmetric; }
    int threads() const { return options_.threads; }

  private:
    // The structures of the list form: a sequence of N_s x 3 arrays (kept alive in `arrays`),
    // one of 3 x 3 boxes, and one periodicity for all or one per structure.
    static std::vector<BatchStructure> listed_structures(const py::handle& points,
                                                         const py::handle& boxes,
                                                         const py::handle& periodic,
                                                         std::vector<DoubleArray>& arrays) {
        const py::sequence xs = checked_sequence(points, "points");
        const py::sequence hs = checked_sequence(boxes, "boxes");
        if (hs.size() != xs.size()) {
            throw py::value_error("boxes has " + std::to_string(hs.size()) + " entries for " +
                                  std::to_string(xs.size()) + " structures (of points)");
        }
        // periodic: one bool or three for every structure, or one of those per structure.
        const py::array flags = numpy_array(periodic, "periodic");
        const bool per_structure = flags.ndim() == 2;
        if (per_structure && static_cast<std::size_t>(flags.shape(0)) != xs.size()) {
            throw py::value_error("periodic has " + std::to_string(flags.shape(0)) +
                                  " entries for " + std::to_string(xs.size()) +
                                  " structures (of points)");
        }
        std::vector<BatchStructure> structures;
        arrays.reserve(xs.size());
        structures.reserve(xs.size());
        for (std::size_t s = 0; s < xs.size(); ++s) {
            try {
                arrays.push_back(points_array(xs[s]));
                const py::object pbc =
                    per_structure ? py::object(flags[py::int_(s)]) : py::object(flags);
                structures.push_back(BatchStructure{
                    box_from_rows(hs[s], pbc, "boxes"),
                    PointsView(arrays.back().data(), std::size_t(arrays.back().shape(0)))});
            } catch (const py::value_error& e) {
                throw py::value_error("structure " + std::to_string(s) + ": " + e.what());
            } catch (const py::type_error& e) {
                throw py::type_error("structure " + std::to_string(s) + ": " + e.what());
            } catch (const Error&) {
                detail::rethrow_for_structure(s);
            }
        }
        return structures;
    }

    // The structures of the concatenated form: structure s owns rows ptr[s]:ptr[s + 1] of
    // `points` and boxes[s]; a box the library refuses is reported with its index.
    static std::vector<BatchStructure> concatenated_structures(const DoubleArray& points,
                                                               const std::vector<std::int64_t>& ptr,
                                                               const py::handle& boxes,
                                                               const py::handle& periodic) {
        const std::size_t count = ptr.size() - 1;
        const DoubleArray h = boxes_array(boxes, count);
        const std::vector<Periodicity> pbc = periodicities(periodic, count);
        std::vector<BatchStructure> structures;
        structures.reserve(count);
        for (std::size_t s = 0; s < count; ++s) {
            const Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> rows(h.data() +
                                                                                      9 * s);
            const PointsView x(points.data() + 3 * ptr[s], std::size_t(ptr[s + 1] - ptr[s]));
            if (same_cell_as_previous(h.data(), s) && pbc[s] == pbc[s - 1]) {
                structures.push_back(BatchStructure{structures.back().box, x});
                continue;
            }
            try {
                structures.push_back(BatchStructure{Box::from_rows(rows, pbc[s]), x});
            } catch (const Error& e) {
                throw py::value_error("structure " + std::to_string(s) + ", boxes[" +
                                      std::to_string(s) + "]: " + e.what());
            }
        }
        return structures;
    }

    // 'o' (per-atom offsets) exists only for a list grouped by i.
    void require_offsets_if_asked(const QuantitySpec& spec) const {
        if (spec.offsets && !options_.with_offsets()) {
            throw py::value_error("quantity 'o' (per-atom offsets) needs a NeighborList made "
                                  "with grouped=True or sorted=True, or with max_neighbors");
        }
    }

    // A pooled list no view refers to (the pool's own reference is the only one), or a new
    // one. Keeps at most two unviewed lists, so memory follows what the caller still holds.
    template <class List>
    static std::shared_ptr<List> free_entry(std::vector<std::shared_ptr<List>>& pool) {
        std::shared_ptr<List> chosen;
        std::vector<std::shared_ptr<List>> kept;
        int unviewed = 0;
        for (auto& entry : pool) {
            const bool viewed = entry.use_count() > 1;
            if (!viewed && !chosen) {
                chosen = entry;
            } else if (!viewed && ++unviewed > 1) {
                continue;
            }
            kept.push_back(std::move(entry));
        }
        pool = std::move(kept);
        if (!chosen) {
            chosen = std::make_shared<List>();
            pool.push_back(chosen);
        }
        return chosen;
    }

    NeighborOptions options_;
    bool per_atom_radii_ = false;
    NeighborSearch search_;
    std::vector<std::shared_ptr<NeighborList>> pool_;
    std::vector<std::shared_ptr<BatchList>> batch_pool_; // of compute_batch(), the same way
    // The buffers of the arrays compute_batch() handed over (copy=True), back for reuse by the
    // next call.
    std::shared_ptr<ColumnRecycler> recycler_ = std::make_shared<ColumnRecycler>();
    std::mutex mutex_;
};

class PyVerletList {
  public:
    PyVerletList(double cutoff, double skin, bool full, int threads, std::size_t max_pairs,
                 const py::object& max_bytes) {
        options_.neighbors.cutoff = cutoff;
        options_.neighbors.max_pairs = max_pairs;
        options_.neighbors.max_bytes = max_bytes_argument(max_bytes);
        options_.skin = skin;
        options_.neighbors.half = !full;
        options_.neighbors.threads = threads;
        options_.neighbors.quantities.vectors = true;
        list_ = VerletList(options_);
    }

    py::object update(const py::handle& points, const py::handle& box, const py::handle& periodic,
                      const std::string& quantities) {
        const DoubleArray x = points_array(points);
        const Box search_box = box_from_rows(box, periodic);
        const QuantitySpec spec = parse_quantities(quantities);
        const PointsView view(x.data(), static_cast<std::size_t>(x.shape(0)));
        {
            py::gil_scoped_release release;
            std::lock_guard<std::mutex> lock(mutex_);
            rebuilt_ = list_.update(search_box, view);
        }
        return pair_columns(list_.pairs(), spec, nullptr);
    }

    double cutoff() const { return options_.neighbors.cutoff; }
    double skin() const { return options_.skin; }
    bool rebuilt() const { return rebuilt_; }
    std::size_t rebuild_count() const { return list_.rebuild_count(); }

  private:
    VerletOptions options_;
    VerletList list_;
    bool rebuilt_ = false;
    std::mutex mutex_;
};

// '"auto", "dense", ...': the names backend= takes, from the library's table of backends.
std::string quoted_backends() {
    std::string text;
    for (const SearchBackend backend : search_backends()) {
        text += std::string(text.empty() ? "" : ", ") + "\"" + backend_name(backend) + "\"";
    }
    return text;
}

} // namespace

void bind_neighbors(py::module_& m) {
    const std::size_t default_max_pairs = NeighborOptions().max_pairs;
    const std::size_t verlet_max_pairs = VerletOptions().neighbors.max_pairs;
    // The docstrings name the defaults and backends of the library; pybind11 copies them.
    const std::string doc = R"doc(
Periodic neighbour list in a triclinic box.

NeighborList(cutoff, full=True, sorted=False, threads=1, backend="auto", max_pairs=)doc" +
                            std::to_string(default_max_pairs) + R"doc(, grouped=False,
             max_bytes=None, max_neighbors=0, tie_tolerance=0.0, symmetric=False)

Pairs (i, j, S) with |D| < cutoff, D = points[j] - points[i] + S @ box, except (i, i, 0).
cutoff may also be a dict {(a, b): cutoff} of integer species pairs (symmetric; a pair of
species missing from it never counts; compute() then takes species=, one per point), or None
for per-atom radii (compute() then takes radii=; a pair counts when d < r_i + r_j).
full=False keeps each pair once (i < j, or i == j with S lexicographically positive).
sorted=True orders pairs by i, then j, then S. grouped=True only groups them by i (each atom's
pairs in the order the search found them, the same for any thread count), in one counting pass;
both give per-atom offsets (quantity 'o'). max_neighbors=k keeps at most k pairs per centre,
nearest first (the k nearest within the cutoff, as machine-learning potentials build their
graphs): each centre's pairs ranked by (d, j, S) and grouped in that order, with offsets; full
lists only (full=False and sorted=True are refused); 0 keeps every pair. tie_tolerance=t keeps
every other pair with d <= d_k + t too, d_k the centre's k-th distance; symmetric=True keeps
(j, i, -S) wherever (i, j, S) is kept, so no edge is kept at one end only. threads=0 uses every core; the result is
identical for any thread count. backend ()doc" +
                            quoted_backends() + R"doc() changes only the speed.
max_pairs refuses a list of more pairs (a batch: in total) before it is allocated, from an
estimate, or as soon as the stored pairs pass it; 0 = no limit. max_bytes does the same for
the list's memory at its peak: the pairs times the bytes of the quantities stored, plus the
working space of grouping or sorting (None: three quarters of the memory this process may use;
0 = no limit).
Array arguments take any array-like of real numbers (floats or integers, any byte order, memory
order or strides; species integers, periodic bools or 0 and 1): another kind of value (bool,
complex, str, object, datetime, ...) raises TypeError, a wrong shape ValueError, each naming the
argument with the dtype and shape it got.)doc";
    py::class_<PyNeighborList>(m, "NeighborList", doc.c_str())
        .def(py::init<const py::object&, bool, bool, int, const std::string&, std::size_t, bool,
                      const py::object&, std::size_t, double, bool>(),
             py::arg("cutoff"), py::arg("full") = true, py::arg("sorted") = false,
             py::arg("threads") = 1, py::arg("backend") = "auto",
             py::arg("max_pairs") = default_max_pairs, py::arg("grouped") = false,
             py::arg("max_bytes") = py::none(), py::arg("max_neighbors") = 0,
             py::arg("tie_tolerance") = 0.0, py::arg("symmetric") = false)
        .def("compute", &PyNeighborList::compute, py::arg("points"), py::arg("box"),
             py::arg("periodic") = true, py::arg("quantities") = "ijSd", py::arg("copy") = true,
             py::arg("radii") = py::none(), py::arg("species") = py::none(),
             py::arg("query") = py::none(),
             R"doc(
Computes the list for N x 3 Cartesian points (anywhere, also outside the box) and a 3 x 3 box
with the lattice vectors as rows; periodic is one bool or three. Returns numpy arrays in the
order of the letters of quantities: i, j (uint32), S (int32, N x 3), d (float64), D (float64,
N x 3), P (uint32, N x 2 pairs (i, j)), o (int64, N + 1 per-atom offsets of a grouped or
sorted list: atom a's pairs are o[a]:o[a + 1]); one letter returns one array. copy=False
returns views of the list's own buffers instead of copies (P and o are always new arrays); a
view stays valid as long as it exists, and later calls never write into memory a view still refers to.
query (indices of points, each once) lists only the pairs of those points, every point a
neighbour: a full list the (i, j, S) with i in query, a half list each pair with both ends in
query once and each pair with one end in it once, i being that end.)doc")
        .def("compute_batch", &PyNeighborList::compute_batch, py::arg("points"), py::arg("boxes"),
             py::arg("periodic") = true, py::arg("quantities") = "ijSd",
             py::arg("batch_ptr") = py::none(), py::arg("copy") = true,
             R"doc(
The lists of many independent structures in one call (one cutoff for all; threads work across
structures). Two forms:
- batch_ptr given (the concatenated format of machine-learning codes): points is N_total x 3,
  the atoms of all structures one after the other; batch_ptr (B + 1 integers from 0 to N_total,
  never decreasing) gives structure s the rows batch_ptr[s]:batch_ptr[s + 1]; boxes is
  B x 3 x 3; i and j index the rows of points (global indices);
- batch_ptr=None: points is a sequence of N_s x 3 arrays and boxes one of 3 x 3 arrays, one per
  structure; i and j number the atoms of their own structure.
Boxes have the lattice vectors as rows; periodic is one bool or three for every structure, or
one row of three per structure (B x 3). Returns a tuple (offsets, *columns): offsets (int64,
B + 1) gives structure s the pairs offsets[s]:offsets[s + 1] of every column, and the columns
are those of compute() over all structures ('o': atom a of structure s has the pairs
o[k]:o[k + 1], k = its index among all structures' atoms). copy=False returns views, as
compute() does. Each structure gets exactly the pairs compute() gives it alone; no pair joins
two structures. Errors name the argument and the structure (boxes[17], points[100:110]) and
return nothing.)doc")
        .def_property_readonly("full", &PyNeighborList::full,
                               "True: both (i, j) and (j, i); False: each pair once.")
        .def_property_readonly("sorted", &PyNeighborList::sorted,
                               "Pairs ordered by i, then j, then S.")
        .def_property_readonly("grouped", &PyNeighborList::grouped,
                               "Pairs grouped by i, in the search's order within each atom.")
        .def_property_readonly("max_neighbors", &PyNeighborList::max_neighbors,
                               "At most this many pairs per centre, nearest first (0: all).")
        .def_property_readonly("tie_tolerance", &PyNeighborList::tie_tolerance,
                               "With max_neighbors: also keep pairs within this of the k-th "
                               "distance.")
        .def_property_readonly("symmetric", &PyNeighborList::symmetric,
                               "With max_neighbors: (j, i, -S) kept wherever (i, j, S) is.")
        .def_property_readonly("threads", &PyNeighborList::threads,
                               "Threads of a search (0: every core).");

    const std::string verlet_doc = R"doc(
Verlet list: candidates within cutoff + skin, rebuilt only when some atom moved far enough
that a pair could be missed: by more than skin / 2 since the build, less the box's strain
since then times the cutoff when the box changes (displacements are measured in the build's
fractional frame, so wrapping or a whole lattice vector never counts), or when the atom count
or periodicity changes.

VerletList(cutoff, skin, full=True, threads=1, max_pairs=)doc" +
                                   std::to_string(verlet_max_pairs) +
                                   R"doc(, max_bytes=None); max_pairs and
max_bytes bound the candidates within cutoff + skin as NeighborList's bound its pairs (0 = no
limit).)doc";
    py::class_<PyVerletList>(m, "VerletList", verlet_doc.c_str())
        .def(py::init<double, double, bool, int, std::size_t, const py::object&>(),
             py::arg("cutoff"), py::arg("skin"), py::arg("full") = true, py::arg("threads") = 1,
             py::arg("max_pairs") = verlet_max_pairs, py::arg("max_bytes") = py::none())
        .def("update", &PyVerletList::update, py::arg("points"), py::arg("box"),
             py::arg("periodic") = true, py::arg("quantities") = "ijSd",
             R"doc(
Refreshes the pairs within the cutoff for these points and box (rebuilding the candidates
when needed) and returns them as NeighborList.compute does (always copies). Pairs come
grouped by increasing i.)doc")
        .def_property_readonly("cutoff", &PyVerletList::cutoff,
                               "r_c: update() gives the pairs with |D| < r_c.")
        .def_property_readonly("skin", &PyVerletList::skin,
                               "Candidates are built at cutoff + skin.")
        .def_property_readonly("rebuilt", &PyVerletList::rebuilt,
                               "Whether the last update() rebuilt the candidates.")
        .def_property_readonly("rebuild_count", &PyVerletList::rebuild_count,
                               "How many times the candidates were built.");
}

} // namespace tricell::python
