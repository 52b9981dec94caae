#include "list_row_simd.h"

namespace corebox {

bool simdListRowsAvailable() {
    static const bool available = __builtin_cpu_supports("avx2");
    return available;
}

}  // namespace corebox
