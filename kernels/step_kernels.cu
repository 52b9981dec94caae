// The one-wait step's kernels (gpu_launch.h, src/cuda/cuda_step.cpp): the words a step reads back,
// the fused end-of-step check and the fused kick-drift. Each computes with the same inline functions
// as the separate kernels it stands for (kineticEnergyOf, verletKick, verletDrift), so a step gives
// the same bits either way. The stage itself is collision_kernels.cu's launchStageWalls.
#include "gpu_common.cuh"
#include "gpu_launch.h"
#include "rk_stage.h"
#include "step_check.cuh"

namespace corebox::gpu {
namespace {

__device__ void resetWords(StepWords* w) {
    *w = StepWords{};
    w->screen[0] = 0xffffffffu;
}

__global__ void resetStepWordsKernel(StepWords* w) { resetWords(w); }

template <class Real>
__global__ void stepCheckKernel(StepCheckArgs<Real> a) {
    const int64_t i = int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
    const ParticleArrays<Real>& p = a.health.p;
    if (i >= p.n) return;
    if (a.xBuilt) {
        Vec3<Real> v = p.v[i], x = p.x[i];
        verletKick(v, a.acceleration[i], a.h);
        verletDrift(x, v, a.dt);
        if (!(norm2(x - a.xBuilt[i]) <= a.limit2)) *a.moves = 1u;  // NaN included
    }
    if (a.health.counts) checkParticle(a.health, a.table, i, a.kineticRow);
}

template <class Real>
__global__ void kickDriftKernel(Vec3<Real>* x, Vec3<Real>* v, const Vec3<Real>* acc, int64_t n, Real h, Real dt, Vec3<Real>* snapshotX,
                                Vec3<Real>* snapshotV, StepWords* reset) {
    const int64_t i = int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
    if (reset && i == 0) resetWords(reset);
    if (i >= n) return;
    Vec3<Real> xi = x[i], vi = v[i];
    if (snapshotX) {
        snapshotX[i] = xi;
        snapshotV[i] = vi;
    }
    verletKick(vi, acc[i], h);
    verletDrift(xi, vi, dt);
    v[i] = vi;
    x[i] = xi;
}

}  // namespace

void launchResetStepWords(StepWords* words, cudaStream_t stream) {
    resetStepWordsKernel<<<1, 1, 0, stream>>>(words);
    checkLaunch("step words kernel");
}

template <class Real>
void launchStepCheck(const StepCheckArgs<Real>& a, cudaStream_t stream) {
    if (a.health.p.n <= 0) return;
    stepCheckKernel<Real><<<blocksFor(a.health.p.n), kBlock, 0, stream>>>(a);
    checkLaunch("step check kernel");
}

template <class Real>
void launchKickDrift(Vec3<Real>* x, Vec3<Real>* v, const Vec3<Real>* a, int64_t n, Real h, Real dt, Vec3<Real>* snapshotX,
                     Vec3<Real>* snapshotV, StepWords* reset, cudaStream_t stream) {
    if (n <= 0 && !reset) return;
    kickDriftKernel<Real><<<blocksFor(n > 0 ? n : 1), kBlock, 0, stream>>>(x, v, a, n, h, dt, snapshotX, snapshotV, reset);
    checkLaunch("kick-drift kernel");
}

#define COREBOX_INSTANTIATE(Real)                                                                            \
    template void launchStepCheck<Real>(const StepCheckArgs<Real>&, cudaStream_t);                           \
    template void launchKickDrift<Real>(Vec3<Real>*, Vec3<Real>*, const Vec3<Real>*, int64_t, Real, Real, Vec3<Real>*, \
                                        Vec3<Real>*, StepWords*, cudaStream_t);
COREBOX_INSTANTIATE(float)
COREBOX_INSTANTIATE(double)
#undef COREBOX_INSTANTIATE

}  // namespace corebox::gpu
