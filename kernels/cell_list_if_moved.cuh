// The cooperative gated cell-list build (cell_list_kernels.cu: launchCellListIfMoved), here so that a
// launch can do work of its own on the cells it built after the build, in the same launch and behind
// the same gate (impact_candidate_kernels.cu: the candidate rows): `after(first, stride)` once the
// arrays are complete, every thread of the grid, where the build ran. NothingAfterBuild: the build alone.
#pragma once

#include <cooperative_groups.h>
#include <cub/block/block_reduce.cuh>
#include <cub/block/block_scan.cuh>

#include <algorithm>
#include <stdexcept>
#include <string>
#include <type_traits>

#include "gpu_common.cuh"
#include "gpu_launch.h"

namespace corebox::gpu {

struct NothingAfterBuild {
    __device__ void operator()(int64_t, int64_t) const {}
};

// sorted[b .. e) in ascending order by insertion, in one thread: a cell's few entries.
__device__ inline void insertionSortRange(int32_t* sorted, int32_t b, int32_t e) {
    for (int32_t x = b + 1; x < e; ++x) {
        const int32_t v = sorted[x];
        int32_t y = x - 1;
        for (; y >= b && sorted[y] > v; --y) sorted[y + 1] = sorted[y];
        sorted[y + 1] = v;
    }
}

// sorted[b .. e) in ascending order by a heap sort in one thread: a cell crowded by a blow-up, which the
// insertion sort of a cell's few entries would take in quadratic time.
__device__ inline void heapSortRange(int32_t* sorted, int32_t b, int32_t e) {
    int32_t* h = sorted + b;
    const int32_t k = e - b;
    auto siftDown = [&](int32_t root, int32_t end) {
        for (;;) {
            int32_t child = 2 * root + 1;
            if (child >= end) return;
            if (child + 1 < end && h[child] < h[child + 1]) ++child;
            if (!(h[root] < h[child])) return;
            const int32_t t = h[root];
            h[root] = h[child];
            h[child] = t;
            root = child;
        }
    };
    for (int32_t root = k / 2 - 1; root >= 0; --root) siftDown(root, k);
    for (int32_t end = k - 1; end > 0; --end) {
        const int32_t t = h[0];
        h[0] = h[end];
        h[end] = t;
        siftDown(0, end);
    }
}

// The counted build of launchCountedCellList in one cooperative launch that does nothing where *moved is
// 0, and clears it otherwise (launchCellListIfMoved): counts, a scan of them (each block a contiguous
// run of cells, the blocks' totals added across), the places, each cell's entries put in ascending index
// (a crowded cell's by a heap sort, so that no fallback build is needed). The same arrays as every build.
template <class Real, class After>
__global__ void __launch_bounds__(kBlock)
    cellListIfMovedKernel(CellListArgs<Real> a, unsigned int* moved, int32_t* blockTotals, After after) {
    if (__ldcg(moved) == 0u) return;  // every block alike: nothing writes it before the first barrier
    cooperative_groups::grid_group grid = cooperative_groups::this_grid();
    using Scan = cub::BlockScan<int32_t, kBlock>;
    using Reduce = cub::BlockReduce<int32_t, kBlock>;
    __shared__ union {
        typename Scan::TempStorage scan;
        typename Reduce::TempStorage reduce;
    } shared;
    __shared__ int32_t blockOffset;
    const int cells = a.geometry.cellCount();
    const int64_t slots = int64_t(cells) + 1;  // the cells and the large particles' tail
    const int64_t first = int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
    const int64_t stride = int64_t(gridDim.x) * blockDim.x;
    for (int64_t c = first; c < slots; c += stride) a.counts[c] = 0;
    grid.sync();
    if (first == 0) *moved = 0u;
    for (int64_t i = first; i < a.n; i += stride) {
        const int key = cellKeyOfParticle(a.geometry, a.split, i, a.x[i]);
        a.keys[i] = uint32_t(key);
        a.indices[i] = atomicAdd(&a.counts[key], 1);
    }
    grid.sync();
    // The scan: block b's run of cells [begin, end), thread t's consecutive share of it.
    const int64_t chunk = (slots + gridDim.x - 1) / gridDim.x;
    const int64_t begin = std::min<int64_t>(int64_t(blockIdx.x) * chunk, slots),
                  end = std::min<int64_t>(begin + chunk, slots);
    const int64_t share = (chunk + blockDim.x - 1) / blockDim.x;
    const int64_t mine = std::min<int64_t>(begin + int64_t(threadIdx.x) * share, end);
    const int64_t mineEnd = std::min<int64_t>(mine + share, end);
    int32_t sum = 0;
    for (int64_t c = mine; c < mineEnd; ++c) sum += a.counts[c];
    int32_t before = 0, total = 0;
    Scan(shared.scan).ExclusiveSum(sum, before, total);
    if (threadIdx.x == 0) blockTotals[blockIdx.x] = total;
    grid.sync();
    int32_t earlier = 0;
    for (int64_t b = threadIdx.x; b < int64_t(blockIdx.x); b += blockDim.x) earlier += __ldcg(&blockTotals[b]);
    __syncthreads();  // the scan's storage becomes the reduction's
    earlier = Reduce(shared.reduce).Sum(earlier);
    if (threadIdx.x == 0) blockOffset = earlier;
    __syncthreads();
    int32_t start = blockOffset + before;
    for (int64_t c = mine; c < mineEnd; ++c) {
        a.cellStart[c] = start;
        start += a.counts[c];
    }
    grid.sync();
    for (int64_t i = first; i < a.n; i += stride) a.sorted[a.cellStart[a.keys[i]] + a.indices[i]] = int32_t(i);
    grid.sync();
    for (int64_t c = first; c < slots; c += stride) {
        const int32_t b = a.cellStart[c], e = c < cells ? a.cellStart[c + 1] : int32_t(a.n);
        if (e - b > kCountedCellMost)
            heapSortRange(a.sorted, b, e);
        else
            insertionSortRange(a.sorted, b, e);
    }
    if constexpr (!std::is_same<After, NothingAfterBuild>::value) {
        grid.sync();
        after(first, stride);
    }
}

// Blocks of cellListIfMovedKernel<Real, After> resident at once (0: no cooperative launch on this device).
template <class Real, class After>
int cellListIfMovedBlocksWith() {
    static const int resident = cooperativeResidentBlocks(cellListIfMovedKernel<Real, After>);
    return resident;
}

// The gated build, then `after`, in one cooperative launch of cellListIfMovedBlocksWith blocks; `what`
// names it in errors. Above cellListBuildIsOneLaunch only, blockTotals of that many blocks.
// Tried and not kept: the launch also a programmatic dependent one (cudaLaunchKernelEx with the
// cooperative and the programmatic-serialisation attributes, waitForPrimary first in the kernel), as the
// round's other kernels are (collision_kernels.cu): the same bits and memcheck clean, but no gain (an
// H200, fp32, separate libraries alternating in one call, three runs each: the sandbox at 10^5 balls
// 18.1 to 18.2 ms a landing frame against 18.2 to 18.3; the 10^6-ball pile 28.3 against 28.4).
template <class Real, class After>
void launchCellListIfMovedWith(const CellListArgs<Real>& a, unsigned int* moved, int32_t* blockTotals, After after,
                               cudaStream_t stream, const char* what) {
    const int blocks = cellListIfMovedBlocksWith<Real, After>();
    if (blocks < 1 || cellListBuildIsOneLaunch(a.n) || a.counts == nullptr)
        throw std::logic_error(std::string(what) + ": not a cooperative counted build");
    CellListArgs<Real> args = a;
    void* params[] = {&args, &moved, &blockTotals, &after};
    const cudaError_t e = cudaLaunchCooperativeKernel(reinterpret_cast<void*>(cellListIfMovedKernel<Real, After>),
                                                      dim3(unsigned(blocks)), dim3(kBlock), params, 0, stream);
    if (e != cudaSuccess) throw DeviceError(std::string(what) + ": " + cudaGetErrorString(e));
}

}  // namespace corebox::gpu
