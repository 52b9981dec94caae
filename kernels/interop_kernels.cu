// Writes particles as renderer instances (particle_instance.h) into device memory: the GL buffer
// mapped through CUDA-GL interop, or a staging buffer copied to the host.
#include "gpu_common.cuh"
#include "gpu_launch.h"

namespace corebox::gpu {
namespace {

template <class Real>
__global__ void fillInstancesKernel(ParticleArrays<Real> p, const Real* radius, InstanceKey key, ParticleInstance* out) {
    const int64_t i = int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
    if (i >= p.n) return;
    const int32_t s = p.species[i];
    out[i] = particleInstanceOf(p.x[i], p.v[i], s, radius[s], key);
}

}  // namespace

template <class Real>
void launchFillInstances(const ParticleArrays<Real>& p, const Real* radius, InstanceKey key, ParticleInstance* out, cudaStream_t stream) {
    fillInstancesKernel<Real><<<blocksFor(p.n), kBlock, 0, stream>>>(p, radius, key, out);
    checkLaunch("instance kernel");
}

template void launchFillInstances<float>(const ParticleArrays<float>&, const float*, InstanceKey, ParticleInstance*, cudaStream_t);
template void launchFillInstances<double>(const ParticleArrays<double>&, const double*, InstanceKey, ParticleInstance*, cudaStream_t);

}  // namespace corebox::gpu
