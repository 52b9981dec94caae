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
    if (a.forecast.moves) forecastParticle(a.forecast, i, p.x[i], p.v[i], a.acceleration[i]);
    if (a.health.counts) checkParticle(a.health, a.table, i, a.kineticRow);
}

template <class Real>
__global__ void kickDriftKernel(KickDriftArgs<Real> a) {
    const int64_t i = int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
    if (!gateOpen(a.gate)) return;
    if (a.reset && i == 0) resetWords(a.reset);
    if (i >= a.n) return;
    Vec3<Real> xi = a.x[i], vi = a.v[i];
    if (a.snapshotX) {
        a.snapshotX[i] = xi;
        a.snapshotV[i] = vi;
    }
    verletKick(vi, a.a[i], a.h);
    verletDrift(xi, vi, a.dt);
    a.vOut[i] = vi;
    a.xOut[i] = xi;
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
void launchKickDrift(const KickDriftArgs<Real>& a, cudaStream_t stream) {
    if (a.n <= 0 && !a.reset) return;
    kickDriftKernel<Real><<<blocksFor(a.n > 0 ? a.n : 1), kBlock, 0, stream>>>(a);
    checkLaunch("kick-drift kernel");
}

#define COREBOX_INSTANTIATE(Real)                                                                            \
    template void launchStepCheck<Real>(const StepCheckArgs<Real>&, cudaStream_t);                           \
    template void launchKickDrift<Real>(const KickDriftArgs<Real>&, cudaStream_t);
COREBOX_INSTANTIATE(float)
COREBOX_INSTANTIATE(double)
#undef COREBOX_INSTANTIATE

}  // namespace corebox::gpu
