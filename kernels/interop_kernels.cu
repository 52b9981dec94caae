// Writes particles into the renderer's instance buffer (mapped through CUDA-GL interop): per
// particle x, y, z, hard-core radius and colour key (species index or speed), 5 floats, the layout
// of src/render/particle_view.h.
#include "gpu_common.cuh"
#include "gpu_launch.h"

namespace corebox::gpu {
namespace {

template <class Real>
__global__ void fillInstancesKernel(ParticleArrays<Real> p, const Real* radius, bool keyIsSpeed, float* out) {
    const int64_t i = int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
    if (i >= p.n) return;
    const Vec3<Real> x = p.x[i];
    const int s = p.species[i];
    float* o = out + 5 * i;
    o[0] = float(x.x);
    o[1] = float(x.y);
    o[2] = float(x.z);
    o[3] = float(radius[s]);
    o[4] = keyIsSpeed ? float(sqrt(double(norm2(p.v[i])))) : float(s);
}

}  // namespace

template <class Real>
void launchFillInstances(const ParticleArrays<Real>& p, const Real* radius, bool keyIsSpeed, float* out, cudaStream_t stream) {
    fillInstancesKernel<Real><<<blocksFor(p.n), kBlock, 0, stream>>>(p, radius, keyIsSpeed, out);
    checkLaunch("instance kernel");
}

template void launchFillInstances<float>(const ParticleArrays<float>&, const float*, bool, float*, cudaStream_t);
template void launchFillInstances<double>(const ParticleArrays<double>&, const double*, bool, float*, cudaStream_t);

}  // namespace corebox::gpu
