// The C boundary: every entry point of tricell.h runs its body through guarded(), which turns
// each exception into a status and the thread's message, so nothing ever crosses into C.
//
// The message lives in a fixed thread_local buffer (no allocation, so recording "out of
// memory" cannot itself run out of memory). Argument checks that only the C side can make
// (NULL pointers, flags that must be 0 or 1) throw tricell::InvalidArgument like the C++ API's
// own checks, so every message, whichever side found the problem, reaches the caller the same
// way. Everything else (cutoffs, positions, boxes) is left to the C++ validation, whose text
// is passed through unchanged, except that a refused pair or memory limit
// (tricell::PairLimitError) names the C field to raise, tricell_neighbor_options.max_pairs or
// max_bytes.
#pragma once

#include "tricell.h"

namespace tricell::c_api {

/// Records `text` (truncated to the buffer) as this thread's message.
void set_message(const char* text) noexcept;

/// Throws InvalidArgument "`function`: `name` must not be NULL" when p is null.
void require_pointer(const void* p, const char* function, const char* name);

/// Throws InvalidArgument "`name` must be 0 or 1 (got `value`)" unless value is 0 or 1.
bool require_flag(int value, const char* name);

/// Runs body(); returns TRICELL_OK (and clears the message) or the status of what it threw.
template <class Body> tricell_status guarded(Body&& body) noexcept;

/// The status of the exception being handled, after recording its message. Call only from a
/// catch block.
tricell_status current_exception_status() noexcept;

template <class Body> tricell_status guarded(Body&& body) noexcept {
    try {
        body();
        set_message("");
        return TRICELL_OK;
    } catch (...) {
        return current_exception_status();
    }
}

} // namespace tricell::c_api
