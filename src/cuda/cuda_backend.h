// CUDA backend on one GPU: the device interface of src/core/backend.h with every model feature of
// the CPU reference, in fp32 or fp64. Kernels (kernels/*.cu) call the same __host__ __device__
// physics as the CPU backend. Particle rows are owned through a DevicePartition (one slice here).
// This library does not link GL: CUDA-GL interop lives in gl_buffer_interop.* (its own library),
// which hands writeInstances a mapped device pointer.
#pragma once

#include <memory>
#include <string>

#include "backend.h"

namespace corebox {

struct CudaBackendOptions {
    Precision precision = Precision::Fp64;
    int device = 0;
};

// Number of usable CUDA devices; 0 when there is no driver or no GPU (never throws).
int cudaDeviceCount();
// "NVIDIA H200 (driver 580.xx, CUDA runtime 13.0)" for logs and benchmark records.
std::string cudaDeviceDescription(int device);

// Throws DeviceError when the device cannot be used.
std::unique_ptr<Backend> makeCudaBackend(const CudaBackendOptions& options);

}  // namespace corebox
