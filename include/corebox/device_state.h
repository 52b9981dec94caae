// Where a simulation's state lives on a GPU, for programs that read it from their own CUDA kernels
// (World::deviceState) and for the backends that report it (src/core/backend.h). No CUDA types: the
// stream is a cudaStream_t passed as void*, the arrays are float3 or double3 by precision.
#pragma once

#include <cstdint>

#include "corebox/types.h"

namespace corebox {

// The state in GPU memory (backend Cuda): arrays of `count` float3 (fp32) or double3 (fp64) in slot
// order (ids() gives the id of each slot), valid once work on `stream` queued before the call is done,
// and until the next call that steps or edits the world (a step may swap or reallocate the arrays).
struct DeviceState {
    int device = -1;               // CUDA ordinal; -1 on the CPU backend
    Precision precision = Precision::Fp64;
    const void* position = nullptr;  // [sigma]
    const void* velocity = nullptr;  // [sigma / tau]
    const int32_t* species = nullptr;
    int64_t count = 0;
    void* stream = nullptr;        // the cudaStream_t the world's work is queued on
};

}  // namespace corebox
