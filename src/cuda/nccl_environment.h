// NCCL's environment, set once before the first NCCL call of the process.
#pragma once

namespace corebox {

// NCCL_NVLS_ENABLE=0 unless the user set it: NVLink SHARP (multicast) needs fabric-manager support
// that the H200 hosts we run on do not offer, and NCCL would otherwise try it and fail to initialise.
void prepareNcclEnvironment();

}  // namespace corebox
