// The impact rounds' candidate rows (gpu_launch.h CandidateRows: the design note): made from a cell
// list at least the largest small contact distance plus the margin wide, where stale in the gated build's
// own cooperative launch (cell_list_if_moved.cuh), and checked for staleness.
#include "cell_list_if_moved.cuh"
#include "gpu_common.cuh"
#include "gpu_launch.h"
#include "impact_candidates.cuh"

namespace corebox::gpu {
namespace {

// The row of the particle at place k of the cells' order (a warp's walks then overlap in the caches).
template <class Real>
__device__ void fillCandidateRow(const CandidateFillArgs<Real>& a, int64_t k) {
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
__global__ void fillCandidatesKernel(CandidateFillArgs<Real> a) {
    const int64_t k = int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
    if (k < a.n) fillCandidateRow(a, k);
}

// The rows, after the cells' build in its launch (cellListIfMovedKernel's `after`).
template <class Real>
struct FillAfterBuild {
    CandidateFillArgs<Real> fill;
    __device__ void operator()(int64_t first, int64_t stride) const {
        for (int64_t k = first; k < fill.n; k += stride) fillCandidateRow(fill, k);
    }
};

template <class Real>
__global__ void candidateStalenessKernel(const Vec3<Real>* x, int64_t n, CandidateRows<Real> rows,
                                         unsigned int* stale) {
    const int64_t i = int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
    if (i < n && leftCandidates(rows, i, x[i])) *stale = 1u;
}

}  // namespace

template <class Real>
void launchFillCandidates(const CandidateFillArgs<Real>& a, cudaStream_t stream) {
    if (a.n <= 0) return;
    fillCandidatesKernel<Real><<<blocksFor(a.n), kBlock, 0, stream>>>(a);
    checkLaunch("candidate rows kernel");
}

template <class Real>
int candidateBuildBlocks() {
    return cellListIfMovedBlocksWith<Real, FillAfterBuild<Real>>();
}

template <class Real>
void launchCellListIfMovedThenFill(const CellListArgs<Real>& a, unsigned int* moved, int32_t* blockTotals,
                                   const CandidateFillArgs<Real>& fill, cudaStream_t stream) {
    launchCellListIfMovedWith(a, moved, blockTotals, FillAfterBuild<Real>{fill}, stream, "candidate cells and rows");
}

template <class Real>
void launchCandidateStaleness(const Vec3<Real>* x, int64_t n, const CandidateRows<Real>& rows, unsigned int* stale,
                              cudaStream_t stream) {
    if (n <= 0) return;
    candidateStalenessKernel<Real><<<blocksFor(n), kBlock, 0, stream>>>(x, n, rows, stale);
    checkLaunch("candidate staleness kernel");
}

#define COREBOX_INSTANTIATE(Real)                                                                         \
    template void launchFillCandidates<Real>(const CandidateFillArgs<Real>&, cudaStream_t);               \
    template int candidateBuildBlocks<Real>();                                                            \
    template void launchCellListIfMovedThenFill<Real>(const CellListArgs<Real>&, unsigned int*, int32_t*, \
                                                      const CandidateFillArgs<Real>&, cudaStream_t);      \
    template void launchCandidateStaleness<Real>(const Vec3<Real>*, int64_t, const CandidateRows<Real>&,  \
                                                 unsigned int*, cudaStream_t);
COREBOX_INSTANTIATE(float)
COREBOX_INSTANTIATE(double)
#undef COREBOX_INSTANTIATE

}  // namespace corebox::gpu
