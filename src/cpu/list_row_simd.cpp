#include "list_row_simd.h"

namespace corebox {

bool simdListRowsAvailable() {
#if defined(__x86_64__)
    static const bool available = __builtin_cpu_supports("avx2");
    return available;
#else
    return false;
#endif
}

}  // namespace corebox
