#include "core/error.h"

#include <cstdio>
#include <cstdlib>

namespace rayproc {

void checkFailed(const char* expr, const char* file, int line) {
    std::fprintf(stderr, "rayproc: internal check failed: %s (%s:%d)\n", expr, file, line);
    std::abort();
}

} // namespace rayproc
