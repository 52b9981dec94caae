// CUDA runtime errors become DeviceError (exit code 4 at the command line), naming the call.
#pragma once

#include <cuda_runtime_api.h>

#include <string>

#include "errors.h"

namespace corebox {

inline void cudaCheck(cudaError_t status, const char* what) {
    if (status != cudaSuccess) throw DeviceError(std::string(what) + ": " + cudaGetErrorString(status));
}

}  // namespace corebox
