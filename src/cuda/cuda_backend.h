// CUDA backend on one GPU: the Backend contract of src/core/backend.h with every model feature of
// the CPU reference, in fp32 or fp64. Kernels (kernels/*.cu) call the same __host__ __device__
// physics as the CPU backend. Particle rows are owned through a DevicePartition (one slice here).
// Only small results (sums, counts, a histogram) cross to the host, except state() and snapshot().
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

// Extra abilities of the CUDA backend for the app: interop writes straight into a mapped GL
// buffer of ParticleInstance (5 floats per particle).
class CudaParticleSource {
public:
    virtual ~CudaParticleSource() = default;
    virtual int device() const = 0;
    virtual void writeInstances(float* deviceInstances, bool keyIsSpeed) = 0;
};

}  // namespace corebox
