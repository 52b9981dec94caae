// All-pairs forces in shared-memory tiles (Nyland, Harris & Prins, GPU Gems 3 ch. 31): each block
// stages blockDim positions and species of the j particles in shared memory, every thread sums the
// force on its own i over the tile. The species-pair table sits in shared memory too. LJ needs only
// 1/R^2 (pair_potential.h): no sqrt in the loop except for the force-shifted cutoff.
#include "gpu_common.cuh"
#include "gpu_launch.h"

namespace corebox::gpu {
namespace {

template <class Real, bool kEnergy>
__global__ void forceKernel(ForceArgs<Real> a) {
    extern __shared__ __align__(16) unsigned char shared[];
    const int s = a.table.count;
    auto* pairs = reinterpret_cast<PairCoefficients<Real>*>(shared);
    auto* tileX = reinterpret_cast<Vec3<Real>*>(pairs + s * s);
    auto* tileSpecies = reinterpret_cast<int32_t*>(tileX + blockDim.x);
    for (int k = threadIdx.x; k < s * s; k += blockDim.x) pairs[k] = a.table.pairs[k];

    const int64_t i = a.begin + int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
    const bool live = i < a.end;
    const Vec3<Real> xi = live ? a.x[i] : Vec3<Real>{0, 0, 0};
    const int si = live ? a.species[i] : 0;
    Vec3<Real> force{0, 0, 0};
    double energy = 0;
    for (int64_t start = 0; start < a.n; start += blockDim.x) {
        __syncthreads();
        const int64_t j = start + threadIdx.x;
        if (j < a.n) {
            tileX[threadIdx.x] = a.x[j];
            tileSpecies[threadIdx.x] = a.species[j];
        }
        __syncthreads();
        const int tile = int(min(int64_t(blockDim.x), a.n - start));
        const PairCoefficients<Real>* row = pairs + si * s;
#pragma unroll 4
        for (int k = 0; k < tile; ++k) {
            const Vec3<Real> r = xi - tileX[k];
            const Real r2 = norm2(r);
            if (r2 == Real(0)) continue;  // itself (or a coincident centre: no direction)
            Real u = 0;
            const Real f = pairForceOverR(row[tileSpecies[k]], r2, kEnergy ? &u : nullptr);
            force += f * r;
            if (kEnergy) energy += double(u);
        }
    }
    if (live) {
        a.acceleration[i] = a.table.invMass[si] * force + a.gravity;
        if (kEnergy) a.pairEnergy[i] = energy;
    }
}

template <class Real>
__global__ void gravityOnlyKernel(ForceArgs<Real> a) {
    const int64_t i = a.begin + int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
    if (i >= a.end) return;
    a.acceleration[i] = a.gravity;
    if (a.pairEnergy) a.pairEnergy[i] = 0;
}

}  // namespace

template <class Real>
void launchForces(const ForceArgs<Real>& a, cudaStream_t stream) {
    const int64_t rows = a.end - a.begin;
    if (rows <= 0) return;
    if (!a.anyPairForce) {
        gravityOnlyKernel<Real><<<blocksFor(rows), kBlock, 0, stream>>>(a);
        checkLaunch("gravity kernel");
        return;
    }
    const int block = kBlock;
    const size_t shared = size_t(a.table.count) * size_t(a.table.count) * sizeof(PairCoefficients<Real>) +
                          size_t(block) * (sizeof(Vec3<Real>) + sizeof(int32_t));
    if (a.pairEnergy) forceKernel<Real, true><<<blocksFor(rows, block), block, shared, stream>>>(a);
    else forceKernel<Real, false><<<blocksFor(rows, block), block, shared, stream>>>(a);
    checkLaunch("force kernel");
}

template void launchForces<float>(const ForceArgs<float>&, cudaStream_t);
template void launchForces<double>(const ForceArgs<double>&, cudaStream_t);

}  // namespace corebox::gpu
