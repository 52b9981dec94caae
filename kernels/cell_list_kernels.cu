// Cell list build on the GPU (layout, rule and neighbour walk in cell_list.h). Deterministic by
// construction, so a run's contact search reads the same arrays every time and the same arrays as the
// host's counting sort:
//   1. key[i] = cell key of particle i, index[i] = i;
//   2. cub::DeviceRadixSort::SortPairs on (key, index): LSD radix sort is stable, so indices stay
//      ascending inside a cell; only the bits a key can use are sorted (cells <= 2^30);
//   3. cellStart[c] = first k with sortedKey[k] >= c, one thread per cell (c = cells gives n): a binary
//      search instead of marking boundaries and filling empty cells by a scan, no atomics and no
//      extra pass.
// The sort costs more than the former atomic scatter for n above a few thousand (a few tens of us per
// build at n ~ 1e5 on an H100); that is the price of an order that does not depend on scheduling.
#include <cub/device/device_radix_sort.cuh>

#include <stdexcept>
#include <string>

#include "gpu_common.cuh"
#include "gpu_launch.h"

namespace corebox::gpu {
namespace {

template <class Real>
__global__ void assignCellKeysKernel(CellListArgs<Real> a) {
    const int64_t i = int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
    if (i >= a.n) return;
    a.keys[i] = uint32_t(cellKeyOf(a.geometry, a.x[i]));
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
    return bytes;
}

template <class Real>
void launchBuildCellList(const CellListArgs<Real>& a, cudaStream_t stream) {
    const int cells = a.geometry.cellCount();
    if (a.n <= 0) {
        cudaMemsetAsync(a.cellStart, 0, size_t(cells + 1) * sizeof(int32_t), stream);
        checkLaunch("cell list reset");
        return;
    }
    assignCellKeysKernel<Real><<<blocksFor(a.n), kBlock, 0, stream>>>(a);
    checkLaunch("cell key kernel");
    const int bits = keyBits(cells);
    size_t bytes = 0;
    cub::DeviceRadixSort::SortPairs(nullptr, bytes, a.keys, a.sortedKeys, a.indices, a.sorted, int(a.n), 0, bits, stream);
    if (bytes > a.scratchBytes) {
        throw std::runtime_error("cell list sort: needs " + std::to_string(bytes) + " bytes of scratch, given " +
                                 std::to_string(a.scratchBytes));
    }
    bytes = a.scratchBytes;
    cub::DeviceRadixSort::SortPairs(a.scratch, bytes, a.keys, a.sortedKeys, a.indices, a.sorted, int(a.n), 0, bits, stream);
    checkLaunch("cell list sort");
    cellStartKernel<<<blocksFor(int64_t(cells) + 1), kBlock, 0, stream>>>(a.sortedKeys, int32_t(a.n), cells, a.cellStart);
    checkLaunch("cell start kernel");
}

template void launchBuildCellList<float>(const CellListArgs<float>&, cudaStream_t);
template void launchBuildCellList<double>(const CellListArgs<double>&, cudaStream_t);

}  // namespace corebox::gpu
