// The contact sweeps' residual (contact_relaxation.h: ContactResidual) reduced to its maxima on the
// device: atomicMax on the bits of non-negative doubles, which order like the values. Shared by the
// Jacobi (contact_kernels.cu) and Gauss-Seidel (contact_gauss_seidel.cu) sweeps.
#pragma once

#include "contact_relaxation.h"
#include "gpu_common.cuh"

namespace corebox::gpu {

__device__ inline void atomicMaxNonNegative(unsigned long long* target, double value) {
    atomicMax(target, static_cast<unsigned long long>(__double_as_longlong(value)));
}

// Both maxima over the warp, left in every lane. Every lane of the warp must call it.
__device__ inline void warpMax(double& speed, double& overlap) {
    for (int offset = 16; offset > 0; offset /= 2) {
        speed = fmax(speed, __shfl_xor_sync(0xffffffffu, speed, offset));
        overlap = fmax(overlap, __shfl_xor_sync(0xffffffffu, overlap, offset));
    }
}

// The residual's maxima over each warp, then one atomic a warp into residual[0..1]: every particle in
// contact has a residual, and 10^5 atomics a sweep on one address queued behind each other (an H200, a
// 10^5-ball pile: 613 sweeps a step took 105 ms a step with an atomic a particle in every sweep, 35 ms
// with one a warp in the last sweep of a batch). Every lane of the warp must call it.
template <class Real>
__device__ inline void addResidual(ContactResidual<Real> r, unsigned long long* residual) {
    double speed = double(r.speedChange), overlap = double(r.overlap);
    warpMax(speed, overlap);
    if (threadIdx.x % 32 != 0) return;
    if (speed > 0) atomicMaxNonNegative(&residual[0], speed);
    if (overlap > 0) atomicMaxNonNegative(&residual[1], overlap);
}

// The block's residual maxima, one atomic a block (every thread of the block calls it): the residual
// of a sweep over 10^5 particles taken one atomic a warp, every sweep, made the sweeps of the 10^5-ball
// pile 20% slower than the launches one by one, which take it once a batch (an H200).
__device__ inline void addBlockResidual(double speed, double overlap, unsigned long long* residual) {
    __shared__ double speedOf[kBlock / 32], overlapOf[kBlock / 32];
    warpMax(speed, overlap);
    const int warp = int(threadIdx.x / 32), lane = int(threadIdx.x % 32);
    if (lane == 0) {
        speedOf[warp] = speed;
        overlapOf[warp] = overlap;
    }
    __syncthreads();
    if (threadIdx.x == 0) {
        for (int w = 1; w < kBlock / 32; ++w) {
            speed = fmax(speed, speedOf[w]);
            overlap = fmax(overlap, overlapOf[w]);
        }
        if (speed > 0) atomicMaxNonNegative(&residual[0], speed);
        if (overlap > 0) atomicMaxNonNegative(&residual[1], overlap);
    }
    __syncthreads();  // the shared rows are free for the next sweep
}

// A cooperative listing's check after `done` sweeps (relaxListingKernel, gaussSeidelListingKernel):
// every thread reads the residual of `slot` (the grid barrier after addBlockResidual made it whole)
// and decides alike whether to stop; the leader (thread 0 of the grid) clears the other slot for the
// next check (read at the check before) and records the outcome in words: [4..5] the first sweep's
// residual, [6..7] the last's (double bits), [8] the sweeps run. Every thread keeps the first sweep's
// overlap in *firstOverlap (set at the first check; RelaxationPlan::sweepCap reads it). Returns whether
// the relaxation stops.
__device__ inline bool checkListingResidual(const RelaxationPlan& plan, int done, int& checks, unsigned long long* slot,
                                            unsigned long long* words, bool leader, double* firstOverlap) {
    const ContactResidual<double> residual{__longlong_as_double((long long)__ldcg(slot)), __longlong_as_double((long long)__ldcg(slot + 1))};
    if (done == 1) *firstOverlap = residual.overlap;
    const bool stop = !plan.continuesAfter(done, residual, *firstOverlap);
    ++checks;
    if (leader) {
        unsigned long long* next = words + 2 * (checks % 2);
        next[0] = next[1] = 0;
        if (done == 1) {
            words[4] = __ldcg(slot);
            words[5] = __ldcg(slot + 1);
        }
        if (stop) {
            words[6] = __ldcg(slot);
            words[7] = __ldcg(slot + 1);
            words[8] = (unsigned long long)done;
        }
    }
    return stop;
}

}  // namespace corebox::gpu
