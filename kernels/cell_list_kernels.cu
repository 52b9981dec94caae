// Cell list build on the GPU (layout, rule and neighbour walk in cell_list.h). Deterministic by
// construction, so a run's contact search reads the same arrays every time and the same arrays as the
// host's counting sort:
//   1. key[i] = cell key of particle i (cells for one kept out of them: cell_list.h), index[i] = i;
//   2. cub::DeviceRadixSort::SortPairs on (key, index): LSD radix sort is stable, so indices stay
//      ascending inside a cell; only the bits a key can use are sorted (cells <= 2^30);
//   3. cellStart[c] = first k with sortedKey[k] >= c, one thread per cell (c = cells gives where the
//      particles kept out of the cells begin, n without them): a binary
//      search instead of marking boundaries and filling empty cells by a scan, no atomics and no
//      extra pass.
// The sort costs more than the former atomic scatter for n above a few thousand (a few tens of us per
// build at n ~ 1e5 on an H100); that is the price of an order that does not depend on scheduling.
// Builds captured into CUDA graphs (DeviceCellList) take a counting sort instead, which puts each
// cell's entries in ascending index after an atomic scatter (launchCountedCellList): the same arrays,
// with the radix sort as its fallback where a cell is crowded (a conditional graph node). The impact
// rounds' builds after a stage's first (DeviceCellList::rebuildIfMoved) are the counting sort in one
// cooperative launch that skips itself where no particle changed cell (launchCellListIfMoved; the kernel
// in cell_list_if_moved.cuh, which the impact rounds' candidate rows launch with work of their own after
// the build), a crowded cell sorted there by a heap sort: the same arrays.
// Up to kOneBlockItems (4096) particles the three steps run in one block (cub::BlockRadixSort, stable
// too, the keys then binary-searched in shared memory), and up to 1024 as a counting sort in shared
// memory (smallCellListKernel): one launch instead of five or so. At that size a build is all launch
// latency, and a collision stage builds one a round (RK4 at N = 1024: 2 to 3 a step).
#include <cooperative_groups.h>
#include <cub/block/block_radix_sort.cuh>
#include <cub/block/block_reduce.cuh>
#include <cub/block/block_scan.cuh>
#include <cub/device/device_radix_sort.cuh>
#include <cub/device/device_scan.cuh>

#include <algorithm>

#include <stdexcept>
#include <string>

#include "cell_list_if_moved.cuh"
#include "gpu_common.cuh"
#include "gpu_launch.h"

namespace corebox::gpu {
namespace {

template <class Real>
__global__ void assignCellKeysKernel(CellListArgs<Real> a) {
    const int64_t i = int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
    if (i >= a.n) return;
    a.keys[i] = uint32_t(cellKeyOfParticle(a.geometry, a.split, i, a.x[i]));
    a.indices[i] = int32_t(i);
}

__global__ void cellStartKernel(const uint32_t* sortedKeys, int32_t n, int cells, int32_t* cellStart) {
    const int64_t c = int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
    if (c > cells) return;
    int32_t lo = 0, hi = n;
    while (lo < hi) {
        const int32_t mid = lo + (hi - lo) / 2;
        if (int64_t(sortedKeys[mid]) < c) lo = mid + 1;
        else hi = mid;
    }
    cellStart[c] = lo;
}

// The whole build of n <= Threads x Items particles in one block: thread t holds particles [t * Items,
// (t + 1) * Items) in a blocked arrangement, the rows past n keyed above every cell (stable: after the
// real ones).
constexpr int64_t kOneBlockItems = 4096;

template <class Real, int Threads, int Items>
__global__ void __launch_bounds__(Threads) oneBlockCellListKernel(CellListArgs<Real> a, int bits, int cells) {
    using Sort = cub::BlockRadixSort<uint32_t, Threads, Items, int32_t>;
    __shared__ union {
        typename Sort::TempStorage sort;
        uint32_t keys[Threads * Items];
    } shared;
    uint32_t keys[Items];
    int32_t values[Items];
    for (int k = 0; k < Items; ++k) {
        const int32_t i = int32_t(threadIdx.x) * Items + k;
        keys[k] = i < a.n ? uint32_t(cellKeyOfParticle(a.geometry, a.split, i, a.x[i])) : 0xffffffffu;
        values[k] = i;
    }
    Sort(shared.sort).Sort(keys, values, 0, bits);
    __syncthreads();  // the sort's storage becomes the sorted keys
    for (int k = 0; k < Items; ++k) {
        const int32_t slot = int32_t(threadIdx.x) * Items + k;
        if (slot >= a.n) break;
        a.sorted[slot] = values[k];
        shared.keys[slot] = keys[k];
    }
    __syncthreads();
    for (int c = int(threadIdx.x); c <= cells; c += Threads) {
        int32_t lo = 0, hi = int32_t(a.n);
        while (lo < hi) {
            const int32_t mid = lo + (hi - lo) / 2;
            if (int64_t(shared.keys[mid]) < c) lo = mid + 1;
            else hi = mid;
        }
        a.cellStart[c] = lo;
    }
}

// Up to 1024 particles (and kSmallSlots cells), in shared memory: a counting sort as the host's
// (host_cell_list.h), counts by atomics (a count: the same in any order), starts by a block scan,
// places by atomics (in no order), then each cell's few entries put in ascending index, one thread a
// cell: the host's arrays. Half the one-block radix sort's time at N = 1024 (its three passes of
// block-wide ranking).
constexpr int kSmallThreads = 1024, kSmallPerThread = 3;
constexpr int kSmallSlots = kSmallThreads * kSmallPerThread;  // cells + 2 at most (maxCellCount(1024) + 2 = 2114)

template <class Real>
__global__ void __launch_bounds__(kSmallThreads) smallCellListKernel(CellListArgs<Real> a, int cells) {
    using Scan = cub::BlockScan<int32_t, kSmallThreads>;
    __shared__ typename Scan::TempStorage scan;
    __shared__ int32_t start[kSmallSlots], cursor[kSmallSlots], order[kSmallThreads];
    const int t = int(threadIdx.x);
    for (int c = t; c < kSmallSlots; c += kSmallThreads) start[c] = 0;
    __syncthreads();
    const int key = t < a.n ? cellKeyOfParticle(a.geometry, a.split, t, a.x[t]) : 0;
    if (t < a.n) atomicAdd(&start[key], 1);
    __syncthreads();
    int32_t counts[kSmallPerThread];
    for (int k = 0; k < kSmallPerThread; ++k) counts[k] = start[t * kSmallPerThread + k];
    Scan(scan).ExclusiveSum(counts, counts);
    for (int k = 0; k < kSmallPerThread; ++k) start[t * kSmallPerThread + k] = cursor[t * kSmallPerThread + k] = counts[k];
    __syncthreads();
    if (t < a.n) order[atomicAdd(&cursor[key], 1)] = t;
    __syncthreads();
    for (int c = t; c <= cells; c += kSmallThreads) {  // insertion sort of the cell's entries by index (and the large ones')
        const int32_t b = start[c], e = start[c + 1];
        insertionSortRange(order, b, e);
    }
    __syncthreads();
    for (int c = t; c <= cells; c += kSmallThreads) a.cellStart[c] = start[c];
    if (t < a.n) a.sorted[t] = order[t];
}

// Key bits to sort: enough for keys 0 .. cells-1 (at least one, which CUB requires).
int keyBits(int cells) {
    int bits = 1;
    while (bits < 31 && (int64_t(1) << bits) < int64_t(cells)) ++bits;
    return bits;
}

}  // namespace

size_t cellListScratchBytes(int64_t n) {
    // Queried for all 32 key bits: an upper bound for the fewer bits a build sorts.
    size_t bytes = 0;
    cub::DeviceRadixSort::SortPairs(nullptr, bytes, static_cast<const uint32_t*>(nullptr), static_cast<uint32_t*>(nullptr),
                                    static_cast<const int32_t*>(nullptr), static_cast<int32_t*>(nullptr), int(n), 0, 32);
    // The counted build's scan of the cell counts (at most maxCellCount(n) cells and the large ones').
    size_t scanBytes = 0;
    cub::DeviceScan::ExclusiveSum(nullptr, scanBytes, static_cast<const int32_t*>(nullptr),
                                  static_cast<int32_t*>(nullptr), int(maxCellCount(n) + 1));
    return std::max(bytes, scanBytes);
}

bool cellListBuildIsOneLaunch(int64_t n) { return n <= kOneBlockItems; }

template <class Real>
void launchBuildCellList(const CellListArgs<Real>& a, cudaStream_t stream) {
    const int cells = a.geometry.cellCount();
    if (a.n <= 0) {
        cudaMemsetAsync(a.cellStart, 0, size_t(cells + 1) * sizeof(int32_t), stream);
        checkLaunch("cell list reset");
        return;
    }
    const int bits = keyBits(cells + 1);  // keys 0 .. cells: cells for the particles kept out of them
    if (a.n <= kSmallThreads && cells + 2 <= kSmallSlots) {
        smallCellListKernel<Real><<<1, kSmallThreads, 0, stream>>>(a, cells);
        checkLaunch("small cell list kernel");
        return;
    }
    if (a.n <= kOneBlockItems) {
        oneBlockCellListKernel<Real, 512, 8><<<1, 512, 0, stream>>>(a, bits, cells);
        checkLaunch("one-block cell list kernel");
        return;
    }
    assignCellKeysKernel<Real><<<blocksFor(a.n), kBlock, 0, stream>>>(a);
    checkLaunch("cell key kernel");
    // No size query first: the scratch was sized for all 32 key bits (cellListScratchBytes), and CUB
    // refuses scratch too small for what it sorts. A query is host time a collision round pays.
    size_t bytes = a.scratchBytes;
    const cudaError_t sorted =
        cub::DeviceRadixSort::SortPairs(a.scratch, bytes, a.keys, a.sortedKeys, a.indices, a.sorted, int(a.n), 0, bits, stream);
    if (sorted != cudaSuccess) {
        throw std::runtime_error("cell list sort (" + std::to_string(a.scratchBytes) + " bytes of scratch): " + cudaGetErrorString(sorted));
    }
    checkLaunch("cell list sort");
    cellStartKernel<<<blocksFor(int64_t(cells) + 1), kBlock, 0, stream>>>(a.sortedKeys, int32_t(a.n), cells, a.cellStart);
    checkLaunch("cell start kernel");
}

namespace {

// The counts zeroed (cells + 1) and the crowded flag cleared, for a counted build: one kernel rather than
// two memsets, since in a graph a memset node's successor began about 10 us after it (an H200, CUPTI, the
// 10^6-ball pile: 2,874 counted builds in 5 s), a kernel's 1.3 us after the kernel before.
__global__ void clearCountsKernel(int32_t* counts, int64_t slots, unsigned int* crowded) {
    const int64_t c = int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
    if (c < slots) counts[c] = 0;
    if (c == 0) *crowded = 0u;
}

template <class Real>
__global__ void countCellKeysKernel(CellListArgs<Real> a) {
    const int64_t i = int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
    if (i >= a.n) return;
    const int key = cellKeyOfParticle(a.geometry, a.split, i, a.x[i]);
    a.keys[i] = uint32_t(key);
    const int32_t rank = atomicAdd(&a.counts[key], 1);
    a.indices[i] = rank;
    if (rank == kCountedCellMost) *a.crowded = 1u;  // a cell of more than kCountedCellMost
}

template <class Real>
__global__ void placeInCellsKernel(CellListArgs<Real> a) {
    const int64_t i = int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
    if (i >= a.n) return;
    a.sorted[a.cellStart[a.keys[i]] + a.indices[i]] = int32_t(i);
}

// Key c's entries (c = cells: the particles kept out of the cells) in ascending index, by insertion:
// a cell holds a few.
__global__ void orderCellsKernel(const int32_t* cellStart, int cells, int32_t n, int32_t* sorted) {
    const int64_t c = int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
    if (c > cells) return;
    const int32_t b = cellStart[c], e = c < cells ? cellStart[c + 1] : n;
    if (e - b > kCountedCellMost) return;  // crowded: the radix build redoes every array
    insertionSortRange(sorted, b, e);
}

__global__ void crowdedGateKernel(cudaGraphConditionalHandle handle, const unsigned int* crowded) {
    cudaGraphSetConditional(handle, *crowded != 0u ? 1u : 0u);
}

}  // namespace

template <class Real>
int cellListIfMovedBlocks() {
    return cellListIfMovedBlocksWith<Real, NothingAfterBuild>();
}
template int cellListIfMovedBlocks<float>();
template int cellListIfMovedBlocks<double>();

template <class Real>
void launchCellListIfMoved(const CellListArgs<Real>& a, unsigned int* moved, int32_t* blockTotals,
                           cudaStream_t stream) {
    launchCellListIfMovedWith(a, moved, blockTotals, NothingAfterBuild{}, stream, "cell list build if moved");
}
template void launchCellListIfMoved<float>(const CellListArgs<float>&, unsigned int*, int32_t*, cudaStream_t);
template void launchCellListIfMoved<double>(const CellListArgs<double>&, unsigned int*, int32_t*, cudaStream_t);

template <class Real>
void launchCountedCellList(const CellListArgs<Real>& a, cudaGraphConditionalHandle crowded, cudaStream_t stream) {
    if (a.n <= kOneBlockItems) throw std::logic_error("launchCountedCellList: a one-launch build");
    const int cells = a.geometry.cellCount();
    clearCountsKernel<<<blocksFor(int64_t(cells) + 1), kBlock, 0, stream>>>(a.counts, int64_t(cells) + 1, a.crowded);
    checkLaunch("cell count clearing kernel");
    countCellKeysKernel<Real><<<blocksFor(a.n), kBlock, 0, stream>>>(a);
    checkLaunch("cell count kernel");
    size_t bytes = a.scratchBytes;
    const cudaError_t scanned =
        cub::DeviceScan::ExclusiveSum(a.scratch, bytes, a.counts, a.cellStart, cells + 1, stream);
    if (scanned != cudaSuccess) throw std::runtime_error(std::string("cell list scan: ") + cudaGetErrorString(scanned));
    placeInCellsKernel<Real><<<blocksFor(a.n), kBlock, 0, stream>>>(a);
    checkLaunch("cell place kernel");
    orderCellsKernel<<<blocksFor(int64_t(cells) + 1), kBlock, 0, stream>>>(a.cellStart, cells, int32_t(a.n), a.sorted);
    checkLaunch("cell order kernel");
    crowdedGateKernel<<<1, 1, 0, stream>>>(crowded, a.crowded);
    checkLaunch("crowded cell gate kernel");
}

template void launchCountedCellList<float>(const CellListArgs<float>&, cudaGraphConditionalHandle, cudaStream_t);
template void launchCountedCellList<double>(const CellListArgs<double>&, cudaGraphConditionalHandle, cudaStream_t);

template void launchBuildCellList<float>(const CellListArgs<float>&, cudaStream_t);
template void launchBuildCellList<double>(const CellListArgs<double>&, cudaStream_t);

}  // namespace corebox::gpu
