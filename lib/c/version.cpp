// The library's version, from the project version CMake passes in (the header's macros are
// checked against the same version when CMake configures).
#include "tricell.h"

#define TRICELL_C_STRINGIFY2(x) #x
#define TRICELL_C_STRINGIFY(x) TRICELL_C_STRINGIFY2(x)

extern "C" const char* tricell_version(void) {
    return TRICELL_C_STRINGIFY(TRICELL_C_LIB_MAJOR) "." TRICELL_C_STRINGIFY(
        TRICELL_C_LIB_MINOR) "." TRICELL_C_STRINGIFY(TRICELL_C_LIB_PATCH);
}
extern "C" int tricell_version_major(void) {
    return TRICELL_C_LIB_MAJOR;
}
extern "C" int tricell_version_minor(void) {
    return TRICELL_C_LIB_MINOR;
}
extern "C" int tricell_version_patch(void) {
    return TRICELL_C_LIB_PATCH;
}
