// Copies bytes to memory that will not be read again soon (a large neighbour list being filled)
// with non-temporal stores: the destination's cache lines are written without first being read
// (an ordinary store reads each line from memory before overwriting it) and do not evict the
// search's working set (benchmarks/ceiling_probe compares the two ways of storing). The threaded
// search copies its batches out this way; on one thread the search stores directly. SSE2 only,
// which every x86-64 has, so there is no run-time dispatch; elsewhere a plain memcpy.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>

#if defined(__x86_64__) || defined(_M_X64)
#include <emmintrin.h>
#define TRICELL_HAVE_STREAM_COPY 1
#endif

namespace tricell::detail {

/// memcpy(to, from, bytes) through non-temporal stores where the processor has them. The stores
/// are fenced before returning, so a thread that later synchronises with this one sees them.
inline void stream_copy(void* to, const void* from, std::size_t bytes) {
#ifdef TRICELL_HAVE_STREAM_COPY
    auto* out = static_cast<unsigned char*>(to);
    const auto* in = static_cast<const unsigned char*>(from);
    const std::size_t head =
        std::min<std::size_t>(bytes, (16 - reinterpret_cast<std::uintptr_t>(out) % 16) % 16);
    std::memcpy(out, in, head);
    std::size_t k = head;
    for (; k + 64 <= bytes; k += 64) {
        const __m128i a = _mm_loadu_si128(reinterpret_cast<const __m128i*>(in + k));
        const __m128i b = _mm_loadu_si128(reinterpret_cast<const __m128i*>(in + k + 16));
        const __m128i c = _mm_loadu_si128(reinterpret_cast<const __m128i*>(in + k + 32));
        const __m128i d = _mm_loadu_si128(reinterpret_cast<const __m128i*>(in + k + 48));
        _mm_stream_si128(reinterpret_cast<__m128i*>(out + k), a);
        _mm_stream_si128(reinterpret_cast<__m128i*>(out + k + 16), b);
        _mm_stream_si128(reinterpret_cast<__m128i*>(out + k + 32), c);
        _mm_stream_si128(reinterpret_cast<__m128i*>(out + k + 48), d);
    }
    for (; k + 16 <= bytes; k += 16) {
        _mm_stream_si128(reinterpret_cast<__m128i*>(out + k),
                         _mm_loadu_si128(reinterpret_cast<const __m128i*>(in + k)));
    }
    std::memcpy(out + k, in + k, bytes - k);
    _mm_sfence();
#else
    std::memcpy(to, from, bytes);
#endif
}

} // namespace tricell::detail
