#include "nccl_environment.h"

#include <cstdlib>

namespace corebox {

void prepareNcclEnvironment() { setenv("NCCL_NVLS_ENABLE", "0", /*overwrite=*/0); }

}  // namespace corebox
