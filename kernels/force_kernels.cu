// All-pairs forces in shared-memory tiles (Nyland, Harris & Prins, GPU Gems 3 ch. 31): each block
// stages blockDim (position, species) entries of the j particles in shared memory and every thread
// sums the forces on its rows over the tile. LJ needs only 1/R^2 (pair_potential.h): no sqrt in the
// loop except for the force-shifted cutoff.
//
// What keeps the loop on the arithmetic units rather than on shared-memory loads:
// - each thread owns kRows rows, so every tile entry it loads serves kRows pairs;
// - a tile entry is one 16-byte (float) or two 16-byte (double) loads: x, y, z and the species;
// - with one species the pair coefficients live in registers; with several they come from a
//   shared-memory table;
// - without a cutoff the loop calls ljForceOverR directly (what pairForceOverR reduces to then).
#include "gpu_common.cuh"
#include "gpu_launch.h"

namespace corebox::gpu {
namespace {

constexpr int kRows = 2;

template <class Real>
struct alignas(16) TileEntry {
    Real x, y, z;
    int32_t species;
};

template <class Real, bool kCutoff>
__device__ __forceinline__ Real pairForce(const PairCoefficients<Real>& p, Real r2, Real* energy) {
    if (kCutoff) return pairForceOverR(p, r2, energy);
    return ljForceOverR(p.sigma2, p.eps4, p.mixing, r2, energy);
}

template <class Real, bool kEnergy, bool kSingleSpecies, bool kCutoff>
__global__ void __launch_bounds__(kBlock) forceKernel(ForceArgs<Real> a) {
    extern __shared__ __align__(16) unsigned char shared[];
    const int s = a.table.count;
    auto* tile = reinterpret_cast<TileEntry<Real>*>(shared);
    auto* pairs = reinterpret_cast<PairCoefficients<Real>*>(tile + blockDim.x);
    if (!kSingleSpecies) {
        for (int k = threadIdx.x; k < s * s; k += blockDim.x) pairs[k] = a.table.pairs[k];
    }
    const PairCoefficients<Real> single = a.table.pairs[0];

    Vec3<Real> xi[kRows], force[kRows];
    int si[kRows];
    double energy[kRows];
    const int64_t rowBase = a.begin + int64_t(blockIdx.x) * blockDim.x * kRows + threadIdx.x;
#pragma unroll
    for (int r = 0; r < kRows; ++r) {
        const int64_t i = rowBase + int64_t(r) * blockDim.x;
        const bool live = i < a.end;
        xi[r] = live ? a.x[i] : Vec3<Real>{0, 0, 0};
        si[r] = live ? a.species[i] : 0;
        force[r] = Vec3<Real>{0, 0, 0};
        energy[r] = 0;
    }
    for (int64_t start = 0; start < a.n; start += blockDim.x) {
        __syncthreads();
        const int64_t j = start + threadIdx.x;
        if (j < a.n) {
            const Vec3<Real> xj = a.x[j];
            tile[threadIdx.x] = TileEntry<Real>{xj.x, xj.y, xj.z, a.species[j]};
        }
        __syncthreads();
        const int count = int(min(int64_t(blockDim.x), a.n - start));
#pragma unroll 4
        for (int k = 0; k < count; ++k) {
            const TileEntry<Real> e = tile[k];
#pragma unroll
            for (int r = 0; r < kRows; ++r) {
                const Vec3<Real> d{xi[r].x - e.x, xi[r].y - e.y, xi[r].z - e.z};
                const Real r2 = norm2(d);
                if (r2 == Real(0)) continue;  // itself (or a coincident centre: no direction)
                const PairCoefficients<Real>& p = kSingleSpecies ? single : pairs[si[r] * s + e.species];
                Real u = 0;
                const Real f = pairForce<Real, kCutoff>(p, r2, kEnergy ? &u : nullptr);
                force[r] += f * d;
                if (kEnergy) energy[r] += double(u);
            }
        }
    }
#pragma unroll
    for (int r = 0; r < kRows; ++r) {
        const int64_t i = rowBase + int64_t(r) * blockDim.x;
        if (i < a.end) {
            a.acceleration[i] = a.table.invMass[si[r]] * force[r] + a.gravity;
            if (kEnergy) a.pairEnergy[i] = energy[r];
        }
    }
}

template <class Real>
__global__ void gravityOnlyKernel(ForceArgs<Real> a) {
    const int64_t i = a.begin + int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
    if (i >= a.end) return;
    a.acceleration[i] = a.gravity;
    if (a.pairEnergy) a.pairEnergy[i] = 0;
}

template <class Real, bool kEnergy, bool kSingle>
void launchVariant(const ForceArgs<Real>& a, bool cutoff, unsigned blocks, size_t shared, cudaStream_t stream) {
    if (cutoff) forceKernel<Real, kEnergy, kSingle, true><<<blocks, kBlock, shared, stream>>>(a);
    else forceKernel<Real, kEnergy, kSingle, false><<<blocks, kBlock, shared, stream>>>(a);
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
    const bool single = a.table.count == 1;
    const size_t shared = size_t(kBlock) * sizeof(TileEntry<Real>) +
                          (single ? 0 : size_t(a.table.count) * size_t(a.table.count) * sizeof(PairCoefficients<Real>));
    const unsigned blocks = blocksFor(rows, kBlock * kRows);
    // The cutoff variant only where one is set; the shifts are all inside pairForceOverR.
    const bool cutoff = a.hasCutoff;
    if (a.pairEnergy) {
        if (single) launchVariant<Real, true, true>(a, cutoff, blocks, shared, stream);
        else launchVariant<Real, true, false>(a, cutoff, blocks, shared, stream);
    } else {
        if (single) launchVariant<Real, false, true>(a, cutoff, blocks, shared, stream);
        else launchVariant<Real, false, false>(a, cutoff, blocks, shared, stream);
    }
    checkLaunch("force kernel");
}

template void launchForces<float>(const ForceArgs<float>&, cudaStream_t);
template void launchForces<double>(const ForceArgs<double>&, cudaStream_t);

}  // namespace corebox::gpu
