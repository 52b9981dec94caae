// Integrator stages on the GPU: the same per-particle arithmetic as the CPU (rk_stage.h). The Butcher
// table is a device copy owned by each backend, so backends with different methods can coexist.
#include "gpu_common.cuh"
#include "gpu_launch.h"
#include "rk_stage.h"

namespace corebox::gpu {
namespace {

template <class Real>
__global__ void stageKernel(StageArgs<Real> a) {
    const int64_t i = int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
    if (i >= a.n) return;
    const double* weights = a.stage >= 0 ? a.tableau->a[a.stage] : a.tableau->b;
    const Vec3<Real> x = rkCombine(weights, a.count, a.dt, a.x0[i], a.kx, size_t(a.n), size_t(i));
    const Vec3<Real> v = rkCombine(weights, a.count, a.dt, a.v0[i], a.kv, size_t(a.n), size_t(i));
    a.xOut[i] = x;
    a.vOut[i] = v;
    if (a.stage >= 0) a.kx[size_t(a.stage) * size_t(a.n) + size_t(i)] = v;
}

template <class Real>
__global__ void errorKernel(StageArgs<Real> a, double tolerance, double* out) {
    const int64_t i = int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
    if (i >= a.n) return;
    const Vec3<Real> zero{0, 0, 0};
    const Vec3<Real> ex = rkCombine(a.tableau->bError, a.count, a.dt, zero, a.kx, size_t(a.n), size_t(i));
    const Vec3<Real> ev = rkCombine(a.tableau->bError, a.count, a.dt, zero, a.kv, size_t(a.n), size_t(i));
    double e = 0;
    for (int k = 0; k < 3; ++k) {
        e += scaledErrorSquared(ex[k], a.x0[i][k], a.xOut[i][k], tolerance);
        e += scaledErrorSquared(ev[k], a.v0[i][k], a.vOut[i][k], tolerance);
    }
    out[i] = e;
}

template <class Real>
__global__ void kickKernel(Vec3<Real>* v, const Vec3<Real>* acc, int64_t n, Real h) {
    const int64_t i = int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
    if (i >= n) return;
    Vec3<Real> vi = v[i];
    verletKick(vi, acc[i], h);
    v[i] = vi;
}

template <class Real>
__global__ void driftKernel(Vec3<Real>* x, const Vec3<Real>* v, int64_t n, Real dt) {
    const int64_t i = int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
    if (i >= n) return;
    Vec3<Real> xi = x[i];
    verletDrift(xi, v[i], dt);
    x[i] = xi;
}

template <class Real>
__global__ void scaleKernel(Vec3<Real>* v, int64_t n, Real alpha) {
    const int64_t i = int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
    if (i < n) v[i] = alpha * v[i];
}

}  // namespace

template <class Real>
void launchStage(const StageArgs<Real>& a, cudaStream_t stream) {
    if (a.n <= 0) return;  // an empty slice (fewer particles than GPUs): a grid of no blocks is an error
    stageKernel<Real><<<blocksFor(a.n), kBlock, 0, stream>>>(a);
    checkLaunch("stage kernel");
}

template <class Real>
void launchErrorNorm(const StageArgs<Real>& a, double tolerance, double* out, cudaStream_t stream) {
    if (a.n <= 0) return;
    errorKernel<Real><<<blocksFor(a.n), kBlock, 0, stream>>>(a, tolerance, out);
    checkLaunch("error kernel");
}

template <class Real>
void launchVerletKick(Vec3<Real>* v, const Vec3<Real>* a, int64_t n, Real h, cudaStream_t stream) {
    if (n <= 0) return;
    kickKernel<Real><<<blocksFor(n), kBlock, 0, stream>>>(v, a, n, h);
    checkLaunch("verlet kick kernel");
}

template <class Real>
void launchVerletDrift(Vec3<Real>* x, const Vec3<Real>* v, int64_t n, Real dt, cudaStream_t stream) {
    if (n <= 0) return;
    driftKernel<Real><<<blocksFor(n), kBlock, 0, stream>>>(x, v, n, dt);
    checkLaunch("verlet drift kernel");
}

template <class Real>
void launchScale(Vec3<Real>* v, int64_t n, Real alpha, cudaStream_t stream) {
    if (n <= 0) return;
    scaleKernel<Real><<<blocksFor(n), kBlock, 0, stream>>>(v, n, alpha);
    checkLaunch("scale kernel");
}

#define COREBOX_INSTANTIATE(Real)                                                                              \
    template void launchStage<Real>(const StageArgs<Real>&, cudaStream_t);                                     \
    template void launchErrorNorm<Real>(const StageArgs<Real>&, double, double*, cudaStream_t);                \
    template void launchVerletKick<Real>(Vec3<Real>*, const Vec3<Real>*, int64_t, Real, cudaStream_t);         \
    template void launchVerletDrift<Real>(Vec3<Real>*, const Vec3<Real>*, int64_t, Real, cudaStream_t);        \
    template void launchScale<Real>(Vec3<Real>*, int64_t, Real, cudaStream_t);
COREBOX_INSTANTIATE(float)
COREBOX_INSTANTIATE(double)
#undef COREBOX_INSTANTIATE

}  // namespace corebox::gpu
