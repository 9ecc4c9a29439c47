// The pair columns: the one struct-of-arrays layout of stored pairs (i, j, S, d, D and per-atom
// offsets) that the single list (NeighborList), the batch list (BatchList) and the distributed
// list (mpi::DistributedPairs) share. The arrays grow without zero-filling (every new entry is
// about to be written) and large ones are placed in huge pages.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <new>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "tricell/export.hpp"
#include "tricell/types.hpp"

namespace tricell {

/// Which per-pair quantities are stored besides i and j.
struct Quantities {
    bool shifts = true;    ///< S, three ints per pair
    bool distances = true; ///< d = |D|
    bool vectors = false;  ///< D, three doubles per pair
};

namespace detail {
/// Memory for a pair array (pair_memory.cpp): a large one is asked for in huge pages.
TRICELL_API void* allocate_pair_memory(std::size_t bytes);
/// Frees what allocate_pair_memory(bytes) returned, with the same `bytes`.
TRICELL_API void free_pair_memory(void* memory, std::size_t bytes) noexcept;

/// An allocator that leaves new elements of trivial types uninitialised, so that growing a pair
/// array does not first write zeros over memory that is about to be overwritten, and that puts
/// large arrays in huge pages.
template <class T> struct UninitializedAllocator : std::allocator<T> {
    template <class U> struct rebind { using other = UninitializedAllocator<U>; };
    UninitializedAllocator() = default;
    template <class U>
    UninitializedAllocator(const UninitializedAllocator<U>&) noexcept {} // NOLINT
    T* allocate(std::size_t n) {
        if (n > std::size_t(-1) / sizeof(T)) {
            throw std::bad_array_new_length();
        }
        return static_cast<T*>(allocate_pair_memory(n * sizeof(T)));
    }
    void deallocate(T* p, std::size_t n) noexcept { free_pair_memory(p, n * sizeof(T)); }
    template <class U> void construct(U* p) noexcept { ::new (static_cast<void*>(p)) U; }
    template <class U, class... Args> void construct(U* p, Args&&... args) {
        ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
    }
};
} // namespace detail

/// The array type of the pair columns: a std::vector whose growth skips zero-filling.
template <class T> using PairArray = std::vector<T, detail::UninitializedAllocator<T>>;

/// Pairs struct-of-arrays, with atom indices of type Index (32-bit local indices, or 64-bit
/// global ids over MPI ranks). A column that was not asked for is empty.
template <class Index> struct BasicPairColumns {
    PairArray<Index> i, j;
    PairArray<std::int32_t> shifts; ///< S, 3 per pair
    PairArray<double> distances;    ///< d = |D|
    PairArray<double> vectors;      ///< D = x_j - x_i + H S, 3 per pair
    /// Per-atom offsets when the pairs are grouped by i: the pairs of atom a are
    /// [offsets[a], offsets[a + 1]). Empty otherwise.
    std::vector<std::size_t> offsets;

    std::size_t size() const { return i.size(); }
    bool empty() const { return i.empty(); }
    Shift shift(std::size_t k) const {
        return Shift(shifts[3 * k], shifts[3 * k + 1], shifts[3 * k + 2]);
    }
    Eigen::Vector3d vector(std::size_t k) const {
        return Eigen::Vector3d(vectors[3 * k], vectors[3 * k + 1], vectors[3 * k + 2]);
    }
    /// Empties every column, keeping the capacity.
    void clear() {
        i.clear();
        j.clear();
        shifts.clear();
        distances.clear();
        vectors.clear();
        offsets.clear();
    }
    /// Reorders every pair column alike: pair k becomes the old pair perm[k] (offsets untouched).
    void permute(const std::vector<std::size_t>& perm) {
        permute_column(i, perm, 1);
        permute_column(j, perm, 1);
        permute_column(shifts, perm, 3);
        permute_column(distances, perm, 1);
        permute_column(vectors, perm, 3);
    }

  private:
    template <class T>
    static void permute_column(PairArray<T>& v, const std::vector<std::size_t>& perm,
                               std::size_t width) {
        if (v.empty()) {
            return;
        }
        PairArray<T> out(width * perm.size());
        for (std::size_t k = 0; k < perm.size(); ++k) {
            for (std::size_t w = 0; w < width; ++w) {
                out[width * k + w] = v[width * perm[k] + w];
            }
        }
        v.swap(out);
    }
};

/// The columns of a NeighborList and a BatchList.
using PairColumns = BasicPairColumns<std::uint32_t>;

} // namespace tricell
