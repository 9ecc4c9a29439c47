#include "scan/range_kernel.hpp"

#include <algorithm>
#include <cmath>

#include "scan/distance_kernel.hpp"

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define TRICELL_HAVE_AVX_RANGE_KERNELS 1
#include <immintrin.h>
#endif

namespace tricell::detail {

namespace {

// Writes hit n: atom a with atom b through range r, D = (dx, dy, dz), d^2 = d_sq, turned into
// its canonical orientation in a half list. The one scalar definition of what a stored pair
// is; the vector versions store the same bits.
inline void store_hit(const RangeScanInput& in, std::uint32_t a, std::uint32_t b,
                      const CandidateRange& r, double dx, double dy, double dz, double d_sq,
                      const PairSlots& out, std::uint32_t n) {
    const std::uint32_t i = in.index[a], j = in.index[b];
    const bool turn = in.orient && (i != j ? i > j : r.self_turn);
    out.i[n] = turn ? j : i;
    out.j[n] = turn ? i : j;
    if (out.shifts != nullptr) {
        std::int32_t s[3] = {r.s[0], r.s[1], r.s[2]};
        if (!in.zero_images) {
            for (int k = 0; k < 3; ++k) {
                s[k] = (s[k] + in.image[3 * a + std::uint32_t(k)]) -
                       in.image[3 * b + std::uint32_t(k)];
            }
        }
        const std::int32_t sign = turn ? -1 : 1;
        out.shifts[3 * n] = sign * s[0];
        out.shifts[3 * n + 1] = sign * s[1];
        out.shifts[3 * n + 2] = sign * s[2];
    }
    if (out.distances != nullptr) {
        out.distances[n] = out.squares ? d_sq : std::sqrt(d_sq);
    }
    if (out.vectors != nullptr) {
        const double t = turn ? -1.0 : 1.0;
        out.vectors[3 * n] = t * dx + 0.0;
        out.vectors[3 * n + 1] = t * dy + 0.0;
        out.vectors[3 * n + 2] = t * dz + 0.0;
    }
}

// The cluster boxes prune the first pruned_ranges ranges of a call (a dense grid's stencil has a
// few dozen); any further ones are tested whole.
constexpr std::uint32_t pruned_ranges = 64;

// The candidates per box of a call (summed over its atoms) from which the boxes pay.
constexpr std::uint64_t prune_threshold = 8;

// What each atom a0 + g of a call tests of range q < pruned_ranges: [b[q][g], e[q][g]), its
// clusters from the first to the last whose box comes within reach of the atom (b >= e: none).
struct Spans {
    std::uint32_t b[pruned_ranges][kernel_group];
    std::uint32_t e[pruned_ranges][kernel_group];
};

// Whether the cluster boxes pay for a call: a box test costs about what a block of candidates costs
// one atom and leaves out only some candidates, so a call prunes only where its atoms meet at
// least prune_threshold candidates per box (a few atoms of a sparse region against rows of an
// atom or two would pay more than they save).
inline bool worth_pruning(const RangeScanInput& in, std::uint32_t a0, std::uint32_t a1,
                          const CandidateRange* ranges, std::uint32_t count) {
    if (in.boxes == nullptr) {
        return false;
    }
    std::uint64_t candidates = 0, boxes = 0;
    for (std::uint32_t q = 0; q < std::min(count, pruned_ranges); ++q) {
        candidates += ranges[q].b1 - ranges[q].b0;
        boxes += ranges[q].c1 - ranges[q].c0 + 1;
    }
    return std::uint64_t(a1 - a0) * candidates >= prune_threshold * boxes;
}

// Whether the box (lower x, y, z, upper x, y, z) lies at least sqrt(reach_sq) from the point
// (tx, ty, tz). The vector versions below compute the same terms.
inline bool beyond(const double* box, double tx, double ty, double tz, double reach_sq) {
    const double gx = std::max(std::max(box[0] - tx, tx - box[3]), 0.0);
    const double gy = std::max(std::max(box[1] - ty, ty - box[4]), 0.0);
    const double gz = std::max(std::max(box[2] - tz, tz - box[5]), 0.0);
    return gx * gx + gy * gy + gz * gz >= reach_sq;
}

// Candidates [b, e) of a range (b >= e: none).
struct Candidates {
    std::uint32_t b, e;
};

// The candidates of range q (ranges[q] = r) that atom a tests: the half stencil takes only b > a in
// the own range, and where the boxes prune (Pruned, spans from a trim) the clusters at either end
// of the range whose boxes lie beyond the cutoff's reach are left out (they hold no pair of a, so
// the pairs and their order stay the same).
template <bool Pruned>
inline Candidates candidates(const RangeScanInput& in, std::uint32_t a, std::uint32_t a0,
                             const CandidateRange& r, std::uint32_t q, const Spans* spans) {
    Candidates c{r.b0, r.b1};
    if (Pruned && q < pruned_ranges) {
        c = Candidates{spans->b[q][a - a0], spans->e[q][a - a0]};
    }
    if (r.own && in.half_stencil) {
        c.b = std::max(c.b, a + 1);
    }
    return c;
}

// Fills spans for atoms [a0, a1) and ranges [0, min(count, pruned_ranges)), one at a time. (Out
// of line like the vector versions: inlined, it lets GCC 12 take the spans it fills for
// uninitialised where the scan reads them.)
[[gnu::noinline]] void trim_scalar(const RangeScanInput& in, std::uint32_t a0, std::uint32_t a1,
                                   const CandidateRange* ranges, std::uint32_t count,
                                   Spans& spans) {
    for (std::uint32_t q = 0; q < std::min(count, pruned_ranges); ++q) {
        const CandidateRange& r = ranges[q];
        for (std::uint32_t a = a0; a < a1; ++a) {
            // a moved by -v, against the unmoved boxes
            const double tx = in.x[a] - r.v[0], ty = in.y[a] - r.v[1], tz = in.z[a] - r.v[2];
            std::uint32_t b = r.b1, e = r.b0;
            bool found = false;
            for (std::uint32_t c = r.c0; c <= r.c1; ++c) {
                if (!beyond(in.boxes + 6 * std::size_t(c), tx, ty, tz, r.reach_sq)) {
                    b = found ? b : in.cluster_start[c];
                    e = in.cluster_start[c + 1];
                    found = true;
                }
            }
            spans.b[q][a - a0] = b;
            spans.e[q][a - a0] = e;
        }
    }
}

// Atom a against candidates [b, e) of range r, one at a time; returns the next free slot.
inline std::uint32_t scan_scalar(const RangeScanInput& in, std::uint32_t a, std::uint32_t b,
                                 std::uint32_t e, const CandidateRange& r, const PairSlots& out,
                                 std::uint32_t n) {
    const double ax = in.x[a], ay = in.y[a], az = in.z[a];
    for (; b < e; ++b) {
        const double dx = (in.x[b] - ax) + r.v[0];
        const double dy = (in.y[b] - ay) + r.v[1];
        const double dz = (in.z[b] - az) + r.v[2];
        const double d_sq = dx * dx + dy * dy + dz * dz;
        if (d_sq < in.cutoff_sq && !(r.own && b == a)) {
            store_hit(in, a, b, r, dx, dy, dz, d_sq, out, n++);
        }
    }
    return n;
}

template <bool Pruned>
std::uint32_t scan_generic(const RangeScanInput& in, std::uint32_t a0, std::uint32_t a1,
                           const CandidateRange* ranges, std::uint32_t count, const PairSlots& out,
                           const Spans* spans, std::uint64_t& tested) {
    std::uint32_t n = 0;
    std::uint64_t t = 0;
    for (std::uint32_t a = a0; a < a1; ++a) {
        for (std::uint32_t q = 0; q < count; ++q) {
            const Candidates c = candidates<Pruned>(in, a, a0, ranges[q], q, spans);
            t += c.e > c.b ? c.e - c.b : 0;
            n = scan_scalar(in, a, c.b, c.e, ranges[q], out, n);
        }
    }
    tested += t;
    return n;
}

#ifdef TRICELL_HAVE_AVX_RANGE_KERNELS

// max(lower - t, t - upper, 0) per lane.
__attribute__((target("avx2"))) inline __m256d gap(__m256d t, double lower, double upper) {
    return _mm256_max_pd(_mm256_max_pd(_mm256_sub_pd(_mm256_set1_pd(lower), t),
                                       _mm256_sub_pd(t, _mm256_set1_pd(upper))),
                         _mm256_setzero_pd());
}

// trim_scalar() with four atoms in the lanes of each half: the same terms, so the same spans.
__attribute__((target("avx2"))) void trim_avx2(const RangeScanInput& in, std::uint32_t a0,
                                               std::uint32_t a1, const CandidateRange* ranges,
                                               std::uint32_t count, Spans& spans) {
    // The atoms, eight lanes (those past a1 repeat the last: their spans go unread).
    alignas(32) double ax[8], ay[8], az[8];
    for (std::uint32_t g = 0; g < 8; ++g) {
        const std::uint32_t a = std::min(a0 + g, a1 - 1);
        ax[g] = in.x[a], ay[g] = in.y[a], az[g] = in.z[a];
    }
    const __m256i bit = _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128);
    for (std::uint32_t q = 0; q < std::min(count, pruned_ranges); ++q) {
        const CandidateRange& r = ranges[q];
        const __m256d vx = _mm256_set1_pd(r.v[0]), vy = _mm256_set1_pd(r.v[1]),
                      vz = _mm256_set1_pd(r.v[2]);
        __m256d t[2][3];
        for (int h = 0; h < 2; ++h) {
            t[h][0] = _mm256_sub_pd(_mm256_load_pd(ax + 4 * h), vx);
            t[h][1] = _mm256_sub_pd(_mm256_load_pd(ay + 4 * h), vy);
            t[h][2] = _mm256_sub_pd(_mm256_load_pd(az + 4 * h), vz);
        }
        const __m256d reach = _mm256_set1_pd(r.reach_sq);
        __m256i b = _mm256_set1_epi32(std::int32_t(r.b1)),
                e = _mm256_set1_epi32(std::int32_t(r.b0));
        __m256i found = _mm256_setzero_si256();
        for (std::uint32_t c = r.c0; c <= r.c1; ++c) {
            const double* box = in.boxes + 6 * std::size_t(c);
            int bits = 0;
            for (int h = 0; h < 2; ++h) {
                const __m256d gx = gap(t[h][0], box[0], box[3]);
                const __m256d gy = gap(t[h][1], box[1], box[4]);
                const __m256d gz = gap(t[h][2], box[2], box[5]);
                const __m256d g_sq =
                    _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(gx, gx), _mm256_mul_pd(gy, gy)),
                                  _mm256_mul_pd(gz, gz));
                bits |= _mm256_movemask_pd(_mm256_cmp_pd(g_sq, reach, _CMP_LT_OQ)) << (4 * h);
            }
            // the lanes near the box, as 32-bit masks
            const __m256i near =
                _mm256_cmpeq_epi32(_mm256_and_si256(_mm256_set1_epi32(bits), bit), bit);
            b = _mm256_blendv_epi8(b, _mm256_set1_epi32(std::int32_t(in.cluster_start[c])),
                                   _mm256_andnot_si256(found, near));
            e = _mm256_blendv_epi8(e, _mm256_set1_epi32(std::int32_t(in.cluster_start[c + 1])),
                                   near);
            found = _mm256_or_si256(found, near);
        }
        _mm256_storeu_si256(reinterpret_cast<__m256i*>(spans.b[q]), b);
        _mm256_storeu_si256(reinterpret_cast<__m256i*>(spans.e[q]), e);
    }
}

// AVX2: four candidates at a time, the hits of a group stored one by one through store_hit().
template <bool Pruned>
__attribute__((target("avx2"))) std::uint32_t
scan_avx2(const RangeScanInput& in, std::uint32_t a0, std::uint32_t a1,
          const CandidateRange* ranges, std::uint32_t count, const PairSlots& out,
          const Spans* spans, std::uint64_t& tested) {
    const __m256d vcut = _mm256_set1_pd(in.cutoff_sq);
    std::uint32_t n = 0;
    std::uint64_t t = 0;
    for (std::uint32_t a = a0; a < a1; ++a) {
        const __m256d vax = _mm256_set1_pd(in.x[a]), vay = _mm256_set1_pd(in.y[a]),
                      vaz = _mm256_set1_pd(in.z[a]);
        for (std::uint32_t q = 0; q < count; ++q) {
            const CandidateRange& r = ranges[q];
            const __m256d vvx = _mm256_set1_pd(r.v[0]), vvy = _mm256_set1_pd(r.v[1]),
                          vvz = _mm256_set1_pd(r.v[2]);
            const Candidates c = candidates<Pruned>(in, a, a0, r, q, spans);
            t += c.e > c.b ? c.e - c.b : 0;
            std::uint32_t b = c.b;
            for (; b + 4 <= c.e; b += 4) {
                const __m256d dx =
                    _mm256_add_pd(_mm256_sub_pd(_mm256_loadu_pd(in.x + b), vax), vvx);
                const __m256d dy =
                    _mm256_add_pd(_mm256_sub_pd(_mm256_loadu_pd(in.y + b), vay), vvy);
                const __m256d dz =
                    _mm256_add_pd(_mm256_sub_pd(_mm256_loadu_pd(in.z + b), vaz), vvz);
                const __m256d d_sq =
                    _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(dx, dx), _mm256_mul_pd(dy, dy)),
                                  _mm256_mul_pd(dz, dz));
                unsigned mask = unsigned(_mm256_movemask_pd(_mm256_cmp_pd(d_sq, vcut, _CMP_LT_OQ)));
                if (r.own && a >= b && a < b + 4) {
                    mask &= ~(1u << (a - b));
                }
                if (mask == 0) {
                    continue;
                }
                alignas(32) double lx[4], ly[4], lz[4], ld[4];
                _mm256_store_pd(lx, dx);
                _mm256_store_pd(ly, dy);
                _mm256_store_pd(lz, dz);
                _mm256_store_pd(ld, d_sq);
                while (mask != 0) {
                    const unsigned lane = unsigned(__builtin_ctz(mask));
                    mask &= mask - 1;
                    store_hit(in, a, b + lane, r, lx[lane], ly[lane], lz[lane], ld[lane], out, n++);
                }
            }
            n = scan_scalar(in, a, b, c.e, r, out, n);
        }
    }
    tested += t;
    return n;
}

// Each of the 256 8-bit masks spread to 24 bits, one bit thrice per lane: which of the 24
// shift components of 8 compressed pairs belong to a pair turned around.
struct TripleMasks {
    std::uint32_t bits[256];
    TripleMasks() {
        for (std::uint32_t m = 0; m < 256; ++m) {
            bits[m] = 0;
            for (std::uint32_t lane = 0; lane < 8; ++lane) {
                if ((m >> lane) & 1u) {
                    bits[m] |= 7u << (3 * lane);
                }
            }
        }
    }
};

const TripleMasks triple_masks;

// max(lower - t, t - upper, 0) per lane (the masked max: GCC 12 warns of the plain one's
// undefined pass-through as of an uninitialised value).
__attribute__((target("avx512f"))) inline __m512d gap(__m512d t, double lower, double upper) {
    const __mmask8 all = 0xFF;
    return _mm512_maskz_max_pd(all,
                               _mm512_maskz_max_pd(all, _mm512_sub_pd(_mm512_set1_pd(lower), t),
                                                   _mm512_sub_pd(t, _mm512_set1_pd(upper))),
                               _mm512_setzero_pd());
}

// trim_scalar() with the atoms in the lanes: the same terms, so the same spans.
__attribute__((target("avx512f,avx512vl,avx512dq"))) void
trim_avx512(const RangeScanInput& in, std::uint32_t a0, std::uint32_t a1,
            const CandidateRange* ranges, std::uint32_t count, Spans& spans) {
    const __mmask8 atoms = __mmask8((1u << (a1 - a0)) - 1);
    const __m512d ax = _mm512_maskz_loadu_pd(atoms, in.x + a0);
    const __m512d ay = _mm512_maskz_loadu_pd(atoms, in.y + a0);
    const __m512d az = _mm512_maskz_loadu_pd(atoms, in.z + a0);
    for (std::uint32_t q = 0; q < std::min(count, pruned_ranges); ++q) {
        const CandidateRange& r = ranges[q];
        const __m512d tx = _mm512_sub_pd(ax, _mm512_set1_pd(r.v[0]));
        const __m512d ty = _mm512_sub_pd(ay, _mm512_set1_pd(r.v[1]));
        const __m512d tz = _mm512_sub_pd(az, _mm512_set1_pd(r.v[2]));
        const __m512d reach = _mm512_set1_pd(r.reach_sq);
        __m256i b = _mm256_set1_epi32(std::int32_t(r.b1)),
                e = _mm256_set1_epi32(std::int32_t(r.b0));
        __mmask8 found = 0;
        for (std::uint32_t c = r.c0; c <= r.c1; ++c) {
            const double* box = in.boxes + 6 * std::size_t(c);
            const __m512d gx = gap(tx, box[0], box[3]);
            const __m512d gy = gap(ty, box[1], box[4]);
            const __m512d gz = gap(tz, box[2], box[5]);
            const __m512d g_sq = _mm512_add_pd(
                _mm512_add_pd(_mm512_mul_pd(gx, gx), _mm512_mul_pd(gy, gy)), _mm512_mul_pd(gz, gz));
            const __mmask8 near = _mm512_cmp_pd_mask(g_sq, reach, _CMP_LT_OQ);
            b = _mm256_mask_mov_epi32(b, __mmask8(near & ~found),
                                      _mm256_set1_epi32(std::int32_t(in.cluster_start[c])));
            e = _mm256_mask_mov_epi32(e, near,
                                      _mm256_set1_epi32(std::int32_t(in.cluster_start[c + 1])));
            found = __mmask8(found | near);
        }
        _mm256_storeu_si256(reinterpret_cast<__m256i*>(spans.b[q]), b);
        _mm256_storeu_si256(reinterpret_cast<__m256i*>(spans.e[q]), e);
    }
}

// D of the `hit` lanes of (dx, dy, dz), compressed and interleaved into 24 doubles at `to` (x, y, z
// of each pair, whole registers: the slots' slack takes the lanes past the hits), negated where
// `turned` (of the compressed lanes) and a zero stored as +0: store_hit()'s t * dx + 0.0 as
// (0 - dx) or (dx + 0).
__attribute__((target("avx512f"))) inline __m512d signed_lanes(__m512d v, __mmask8 hit,
                                                               __mmask8 turned) {
    const __m512d zero = _mm512_setzero_pd();
    const __m512d c = _mm512_maskz_compress_pd(hit, v);
    return _mm512_mask_sub_pd(_mm512_add_pd(c, zero), turned, zero, c);
}

__attribute__((target("avx512f"))) inline void
store_vectors(double* to, __mmask8 hit, __mmask8 turned, __m512d dx, __m512d dy, __m512d dz) {
    const __m512d x = signed_lanes(dx, hit, turned), y = signed_lanes(dy, hit, turned),
                  z = signed_lanes(dz, hit, turned);
    // x and y into their places of each register (index 8 + k: y's lane k), then z over the gaps.
    const __m512d xy0 = _mm512_permutex2var_pd(x, _mm512_setr_epi64(0, 8, 0, 1, 9, 0, 2, 10), y);
    const __m512d xy1 = _mm512_permutex2var_pd(x, _mm512_setr_epi64(0, 3, 11, 0, 4, 12, 0, 5), y);
    const __m512d xy2 = _mm512_permutex2var_pd(x, _mm512_setr_epi64(13, 0, 6, 14, 0, 7, 15, 0), y);
    _mm512_storeu_pd(to, _mm512_permutex2var_pd(xy0, _mm512_setr_epi64(0, 1, 8, 3, 4, 9, 6, 7), z));
    _mm512_storeu_pd(to + 8,
                     _mm512_permutex2var_pd(xy1, _mm512_setr_epi64(10, 1, 2, 11, 4, 5, 12, 7), z));
    _mm512_storeu_pd(to + 16,
                     _mm512_permutex2var_pd(xy2, _mm512_setr_epi64(0, 13, 2, 3, 14, 5, 6, 15), z));
}

// AVX-512: eight candidates at a time through masked loads; a block's hits are compressed in
// registers and stored whole (the slots have kernel_slack room): i, j (turned with min/max in a
// half list), d, D (store_vectors()) and, with every image 0, S as the range's shift or its
// negative per lane. S with images is written per hit from the compressed lanes.
template <bool Pruned>
__attribute__((target("avx512f,avx512vl,avx512dq,bmi2"))) std::uint32_t
scan_avx512(const RangeScanInput& in, std::uint32_t a0, std::uint32_t a1,
            const CandidateRange* ranges, std::uint32_t count, const PairSlots& out,
            const Spans* spans, std::uint64_t& tested) {
    // Locals: the vector stores below may alias anything, so fields read through `in` and
    // `out` would be read again after each.
    const double* const x = in.x;
    const double* const y = in.y;
    const double* const z = in.z;
    const std::uint32_t* const index = in.index;
    const std::int32_t* const image = in.image;
    const bool orient = in.orient, zero_images = in.zero_images;
    const double cutoff_sq = in.cutoff_sq;
    std::uint32_t* const oi = out.i;
    std::uint32_t* const oj = out.j;
    std::int32_t* const os = out.shifts;
    double* const od = out.distances;
    double* const ov = out.vectors;
    const bool squares = out.squares;
    const __m512d vcut = _mm512_set1_pd(cutoff_sq);
    const __m256i lanes = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
    std::uint32_t n = 0;
    std::uint64_t t = 0;
    for (std::uint32_t a = a0; a < a1; ++a) {
        const __m512d vax = _mm512_set1_pd(x[a]), vay = _mm512_set1_pd(y[a]),
                      vaz = _mm512_set1_pd(z[a]);
        const __m256i vi = _mm256_set1_epi32(std::int32_t(index[a]));
        for (std::uint32_t q = 0; q < count; ++q) {
            const CandidateRange& r = ranges[q];
            const Candidates span = candidates<Pruned>(in, a, a0, r, q, spans);
            if (span.b >= span.e) {
                continue;
            }
            t += span.e - span.b;
            const std::uint32_t b1 = span.e;
            const bool own = r.own, self_turn = r.self_turn;
            const std::int32_t rs[3] = {r.s[0], r.s[1], r.s[2]};
            const __m512d vvx = _mm512_set1_pd(r.v[0]), vvy = _mm512_set1_pd(r.v[1]),
                          vvz = _mm512_set1_pd(r.v[2]);
            // S of 8 pairs through r with every image 0: 24 ints.
            const __m512i s_lo =
                _mm512_setr_epi32(rs[0], rs[1], rs[2], rs[0], rs[1], rs[2], rs[0], rs[1], rs[2],
                                  rs[0], rs[1], rs[2], rs[0], rs[1], rs[2], rs[0]);
            const __m256i s_hi =
                _mm256_setr_epi32(rs[1], rs[2], rs[0], rs[1], rs[2], rs[0], rs[1], rs[2]);
            for (std::uint32_t b = span.b; b < b1; b += 8) {
                const __mmask8 valid =
                    b1 - b >= 8 ? __mmask8(0xFF) : __mmask8((1u << (b1 - b)) - 1);
                const __m512d dx =
                    _mm512_add_pd(_mm512_sub_pd(_mm512_maskz_loadu_pd(valid, x + b), vax), vvx);
                const __m512d dy =
                    _mm512_add_pd(_mm512_sub_pd(_mm512_maskz_loadu_pd(valid, y + b), vay), vvy);
                const __m512d dz =
                    _mm512_add_pd(_mm512_sub_pd(_mm512_maskz_loadu_pd(valid, z + b), vaz), vvz);
                const __m512d d_sq =
                    _mm512_add_pd(_mm512_add_pd(_mm512_mul_pd(dx, dx), _mm512_mul_pd(dy, dy)),
                                  _mm512_mul_pd(dz, dz));
                unsigned hit = _mm512_mask_cmp_pd_mask(valid, d_sq, vcut, _CMP_LT_OQ);
                const bool self_lane = a >= b && a < b + 8;
                if (own && self_lane) {
                    hit &= ~(1u << (a - b));
                }
                // No branch on the hits (a block holds none about as often as some): a block
                // without any stores registers that the next one overwrites.
                const std::uint32_t found = std::uint32_t(__builtin_popcount(hit));
                const __m256i vj = _mm256_maskz_loadu_epi32(__mmask8(hit), index + b);
                // Lanes turned around (a half list): i > j, or an atom's own image the range turns.
                unsigned turn = 0;
                if (orient) {
                    turn = _mm256_mask_cmpgt_epu32_mask(__mmask8(hit), vi, vj);
                    if (self_lane && self_turn) {
                        turn |= hit & (1u << (a - b));
                    }
                    _mm256_storeu_si256(
                        reinterpret_cast<__m256i*>(oi + n),
                        _mm256_maskz_compress_epi32(__mmask8(hit), _mm256_min_epu32(vi, vj)));
                    _mm256_storeu_si256(
                        reinterpret_cast<__m256i*>(oj + n),
                        _mm256_maskz_compress_epi32(__mmask8(hit), _mm256_max_epu32(vi, vj)));
                } else {
                    _mm256_storeu_si256(reinterpret_cast<__m256i*>(oi + n), vi);
                    _mm256_storeu_si256(reinterpret_cast<__m256i*>(oj + n),
                                        _mm256_maskz_compress_epi32(__mmask8(hit), vj));
                }
                // The turned lanes among the stored ones, in their compressed places.
                const unsigned turned = unsigned(_pext_u32(turn, hit));
                if (od != nullptr) {
                    // d^2 for now: the square roots are taken together at the end.
                    _mm512_storeu_pd(od + n, _mm512_maskz_compress_pd(__mmask8(hit), d_sq));
                }
                if (os != nullptr && zero_images) {
                    // S of the 8 pairs, negated where turned.
                    const std::uint32_t negative = triple_masks.bits[turned];
                    std::int32_t* s = os + 3 * std::size_t(n);
                    _mm512_storeu_si512(s, _mm512_mask_sub_epi32(s_lo, __mmask16(negative),
                                                                 _mm512_setzero_si512(), s_lo));
                    _mm256_storeu_si256(reinterpret_cast<__m256i*>(s + 16),
                                        _mm256_mask_sub_epi32(s_hi, __mmask8(negative >> 16),
                                                              _mm256_setzero_si256(), s_hi));
                }
                if (ov != nullptr) {
                    store_vectors(ov + 3 * std::size_t(n), __mmask8(hit), __mmask8(turned), dx, dy,
                                  dz);
                }
                if (os != nullptr && !zero_images) {
                    alignas(32) std::int32_t lb[8];
                    _mm256_store_si256(reinterpret_cast<__m256i*>(lb),
                                       _mm256_maskz_compress_epi32(__mmask8(hit), lanes));
                    for (std::uint32_t h = 0; h < found; ++h) {
                        const std::int32_t sign = (turned >> h) & 1u ? -1 : 1;
                        const std::size_t p = std::size_t(n + h);
                        const std::uint32_t c = b + std::uint32_t(lb[h]);
                        for (std::uint32_t k = 0; k < 3; ++k) {
                            os[3 * p + k] = sign * ((rs[k] + image[3 * a + k]) - image[3 * c + k]);
                        }
                    }
                }
                n += found;
            }
        }
    }
    tested += t;
    if (od != nullptr && !squares) {
        for (std::uint32_t k = 0; k < n; k += 8) {
            // only the stored lanes: the slack past n may hold anything (a trapping NaN)
            const __mmask8 tail = n - k >= 8 ? __mmask8(0xff) : __mmask8((1u << (n - k)) - 1);
            _mm512_mask_storeu_pd(od + k, tail,
                                  _mm512_maskz_sqrt_pd(tail, _mm512_maskz_loadu_pd(tail, od + k)));
        }
    }
    return n;
}

#endif

// A kernel version: the blocks of `Blocks<true>` over the spans `trim` leaves where the boxes
// pay, of `Blocks<false>` over whole ranges otherwise (no span looked up per atom and range).
using Trim = void (*)(const RangeScanInput&, std::uint32_t, std::uint32_t, const CandidateRange*,
                      std::uint32_t, Spans&);
using Blocks = std::uint32_t (*)(const RangeScanInput&, std::uint32_t, std::uint32_t,
                                 const CandidateRange*, std::uint32_t, const PairSlots&,
                                 const Spans*, std::uint64_t&);
template <Trim trim, Blocks pruned, Blocks whole>
std::uint32_t scan(const RangeScanInput& in, std::uint32_t a0, std::uint32_t a1,
                   const CandidateRange* ranges, std::uint32_t count, const PairSlots& out,
                   std::uint64_t& tested) {
    if (worth_pruning(in, a0, a1, ranges, count)) {
        Spans spans;
        trim(in, a0, a1, ranges, count, spans);
        return pruned(in, a0, a1, ranges, count, out, &spans, tested);
    }
    return whole(in, a0, a1, ranges, count, out, nullptr, tested);
}

} // namespace

std::vector<RangeKernelVersion> range_kernels() {
    std::vector<RangeKernelVersion> out;
#ifdef TRICELL_HAVE_AVX_RANGE_KERNELS
    __builtin_cpu_init();
    if (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl") &&
        __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("bmi2")) {
        out.push_back({"avx512", scan<trim_avx512, scan_avx512<true>, scan_avx512<false>>});
    }
    if (__builtin_cpu_supports("avx2")) {
        out.push_back({"avx2", scan<trim_avx2, scan_avx2<true>, scan_avx2<false>>});
    }
#endif
    out.push_back({"generic", scan<trim_scalar, scan_generic<true>, scan_generic<false>>});
    return out;
}

RangeKernel range_kernel() {
    static const RangeKernel chosen = range_kernels().front().scan;
    return chosen;
}

} // namespace tricell::detail
