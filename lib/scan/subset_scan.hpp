// The subset search's part of the candidate scan (CandidateScanner's members for a
// NeighborOptions::query). A subset search flags the query atoms and takes as first atom of a
// test only a query atom, gathered from each range into the kernel's groups, so the tests are
// those of the query's own pairs. A full subset list has the backend binned for a full list.
// A half subset list has it binned for a half list (each unordered candidate once) and keeps a
// pair when either end is a query atom: of (range A, range B, s) the query atoms of A are
// tested against B through s, then the query atoms of B against A through -s, over the span of
// A's atoms outside the query only (where a cell lists its query atoms first, as the stable
// cell sort does for a query of the first indices, just those atoms), keeping the hits outside
// the query. A pair of two query atoms takes its canonical orientation, as in the half list; a
// pair with one end in the query is oriented from that end. The own range is scanned from its
// query atoms against all of it, as a full list, keeping a pair of two query atoms in its
// canonical orientation only.
//
// Included at the end of candidate_scan.hpp, which declares these members; not on its own.
#pragma once

namespace tricell::detail {

// A half subset list's (range, range, shift) triple (see the comment atop this file). The
// own range (b0 == a0 in a half list) is the own cell scanned as a full list, then the rest
// of the run as an ordinary triple.
inline void CandidateScanner::half_subset_ranges(std::uint32_t a0, std::uint32_t a1,
                                                 std::uint32_t b0, std::uint32_t b1,
                                                 const ImageShift& s, bool own) {
    if (own) {
        subset_ranges(a0, a1, a0, a1, s, Scan::own);
        if (a1 < b1) {
            half_subset_ranges(a0, a1, a1, b1, s, false);
        }
        return;
    }
    subset_ranges(a0, a1, b0, b1, s, Scan::plain);
    std::uint32_t first = a0, end = a1; // the span of A's atoms outside the query
    while (first < end && query_[first] != 0) {
        ++first;
    }
    while (end > first && query_[end - 1] != 0) {
        --end;
    }
    if (first < end) {
        subset_ranges(b0, b1, first, end, reversed(s), Scan::to_others);
    }
}

// The query atoms of [a0, a1) as first atoms, in groups of up to kernel_group, against
// [b0, b1) through s (with Scan::own every b but a itself).
inline void CandidateScanner::subset_ranges(std::uint32_t a0, std::uint32_t a1, std::uint32_t b0,
                                            std::uint32_t b1, const ImageShift& s, Scan how) {
    std::uint32_t group[kernel_group];
    std::uint32_t count = 0;
    for (std::uint32_t a = a0; a < a1; ++a) {
        if (query_[a] == 0) {
            continue;
        }
        group[count++] = a;
        if (count == kernel_group) {
            tests_ += std::uint64_t(count) * std::uint64_t(b1 - b0);
            scan(group, count, b0, b1, s, how);
            count = 0;
        }
    }
    if (count > 0) {
        tests_ += std::uint64_t(count) * std::uint64_t(b1 - b0);
        scan(group, count, b0, b1, s, how);
    }
}

// Whether a half list may turn a hit of the block around: a subset list turns only pairs of
// two query atoms, which a scan from the other range or one of the own range (canonical
// already) does not keep.
inline bool CandidateScanner::may_turn(Scan how, std::uint32_t start, const std::uint32_t* hits,
                                       std::uint32_t found) const {
    if (query_ == nullptr) {
        return true;
    }
    if (how != Scan::plain) {
        return false;
    }
    for (std::uint32_t h = 0; h < found; ++h) {
        if (query_[start + hits[h] % kernel_block] != 0) {
            return true;
        }
    }
    return false;
}

// Drops the hits (a, b) with b a query atom (Scan::to_others: found from a already).
inline std::uint32_t CandidateScanner::drop_queried(std::uint32_t start, std::uint32_t* hits,
                                                    double* d_sq, std::uint32_t found) const {
    std::uint32_t kept = 0;
    for (std::uint32_t h = 0; h < found; ++h) {
        hits[kept] = hits[h];
        d_sq[kept] = d_sq[h];
        kept += query_[start + hits[h] % kernel_block] == 0 ? 1u : 0u;
    }
    return kept;
}

// A half subset list drops the hits (a, b) with b a query atom too that are not in the
// canonical orientation: that pair is kept when found from b. Returns how many remain.
inline std::uint32_t CandidateScanner::drop_mirrored(const Side& side, std::uint32_t start,
                                                     std::uint32_t* hits, double* d_sq,
                                                     std::uint32_t found) const {
    std::uint32_t kept = 0;
    for (std::uint32_t h = 0; h < found; ++h) {
        const std::uint32_t g = hits[h] / kernel_block;
        const std::uint32_t b = start + hits[h] % kernel_block;
        hits[kept] = hits[h];
        d_sq[kept] = d_sq[h];
        const bool mirrored =
            query_[b] != 0 && flip(side.i[g], index_[b], side.sa[g] - image_[3 * b],
                                   side.sb[g] - image_[3 * b + 1], side.sc[g] - image_[3 * b + 2]);
        kept += mirrored ? 0u : 1u;
    }
    return kept;
}

} // namespace tricell::detail
