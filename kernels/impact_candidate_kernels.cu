// The impact rounds' candidate rows (gpu_launch.h CandidateRows: the design note): made from a cell
// list at least the largest small contact distance plus the margin wide, and checked for staleness.
#include "gpu_common.cuh"
#include "gpu_launch.h"
#include "impact_candidates.cuh"

namespace corebox::gpu {
namespace {

// A thread a particle, in the cells' order (a warp's walks overlap in the caches).
template <class Real>
__global__ void fillCandidatesKernel(CandidateFillArgs<Real> a) {
    const int64_t k = int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
    if (k >= a.n || (a.gate && *a.gate == 0u)) return;
    const int64_t i = a.grid.sorted[k];
    const Vec3<Real> xi = a.x[i];
    const Real ri = a.radius[a.species[i]];
    int32_t* row = a.rows + size_t(i) * size_t(a.slots);
    int32_t count = 0;
    forEachNeighbour(a.grid, xi, ri, [&](int64_t j) {
        if (j == i) return;
        const Real reach = ri + a.radius[a.species[j]] + a.margin;
        if (!(norm2(xi - a.x[j]) < reach * reach)) return;
        if (count < a.slots) row[count] = int32_t(j);
        ++count;
    });
    a.counts[i] = count;
    a.xBuilt[i] = xi;
}

template <class Real>
__global__ void candidateStalenessKernel(const Vec3<Real>* x, const Vec3<Real>* xBuilt, int64_t n, Real halfMargin2,
                                         unsigned int* flags) {
    const int64_t i = int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
    if (i >= n) return;
    CandidateRows<Real> c;
    c.xBuilt = xBuilt;
    c.halfMargin2 = halfMargin2;
    if (leftCandidates(c, i, x[i])) {
        flags[0] = 1u;
        flags[1] = 1u;
    }
}

}  // namespace

template <class Real>
void launchFillCandidates(const CandidateFillArgs<Real>& a, cudaStream_t stream) {
    if (a.n <= 0) return;
    fillCandidatesKernel<Real><<<blocksFor(a.n), kBlock, 0, stream>>>(a);
    checkLaunch("candidate rows kernel");
}

template <class Real>
void launchCandidateStaleness(const Vec3<Real>* x, const Vec3<Real>* xBuilt, int64_t n, Real halfMargin2,
                              unsigned int* flags, cudaStream_t stream) {
    if (n <= 0) return;
    candidateStalenessKernel<Real><<<blocksFor(n), kBlock, 0, stream>>>(x, xBuilt, n, halfMargin2, flags);
    checkLaunch("candidate staleness kernel");
}

#define COREBOX_INSTANTIATE(Real)                                                                                    \
    template void launchFillCandidates<Real>(const CandidateFillArgs<Real>&, cudaStream_t);                          \
    template void launchCandidateStaleness<Real>(const Vec3<Real>*, const Vec3<Real>*, int64_t, Real, unsigned int*, \
                                                 cudaStream_t);
COREBOX_INSTANTIATE(float)
COREBOX_INSTANTIATE(double)
#undef COREBOX_INSTANTIATE

}  // namespace corebox::gpu
