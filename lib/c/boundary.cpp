#include "boundary.hpp"

#include <cstring>
#include <exception>
#include <new>
#include <string>

#include "tricell/error.hpp"

namespace tricell::c_api {

namespace {
constexpr std::size_t message_capacity = 1024;
thread_local char message[message_capacity] = "";
} // namespace

void set_message(const char* text) noexcept {
    std::size_t length = std::strlen(text);
    if (length >= message_capacity) {
        length = message_capacity - 1;
    }
    std::memcpy(message, text, length);
    message[length] = '\0';
}

namespace {
// A refused pair or memory limit in C terms: the field a C caller raises
// (tricell_verlet_options has them too, in its member neighbors). Composing the text
// allocates; should that fail, the C++ text is recorded instead.
void set_pair_limit_message(const PairLimitError& e) noexcept {
    try {
        const std::string field =
            e.which() == PairLimitError::Limit::bytes ? "max_bytes" : "max_pairs";
        set_message(
            e.message_for(field + " = " + e.limit_text(), "tricell_neighbor_options." + field)
                .c_str());
    } catch (...) {
        set_message(e.what());
    }
}
} // namespace

void require_pointer(const void* p, const char* function, const char* name) {
    if (p == nullptr) {
        detail::fail<InvalidArgument>(function, ": ", name, " must not be NULL");
    }
}

bool require_flag(int value, const char* name) {
    if (value != 0 && value != 1) {
        detail::fail<InvalidArgument>(name, " must be 0 or 1 (got ", value, ")");
    }
    return value == 1;
}

tricell_status current_exception_status() noexcept {
    try {
        throw;
    } catch (const GeometryError& e) {
        set_message(e.what());
        return TRICELL_ERROR_GEOMETRY;
    } catch (const PairLimitError& e) {
        set_pair_limit_message(e);
        return TRICELL_ERROR_INVALID_ARGUMENT;
    } catch (const InvalidArgument& e) {
        set_message(e.what());
        return TRICELL_ERROR_INVALID_ARGUMENT;
    } catch (const std::bad_alloc&) {
        set_message("out of memory");
        return TRICELL_ERROR_OUT_OF_MEMORY;
    } catch (const std::exception& e) {
        set_message(e.what());
        return TRICELL_ERROR_INTERNAL;
    } catch (...) {
        set_message("unknown C++ exception");
        return TRICELL_ERROR_INTERNAL;
    }
}

} // namespace tricell::c_api

extern "C" const char* tricell_last_error(void) {
    return tricell::c_api::message;
}
