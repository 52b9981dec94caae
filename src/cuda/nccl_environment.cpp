#include "nccl_environment.h"

#include <cstdlib>

namespace corebox {

void prepareNcclEnvironment() {
    // overwrite = 0: a value the user exported (to test NVLS where a machine has it) wins.
    ::setenv("NCCL_NVLS_ENABLE", "0", 0);
}

}  // namespace corebox
