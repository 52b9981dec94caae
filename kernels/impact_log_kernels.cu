// The contact log's order on the device (gpu_launch.h launchSortImpactLog): the resolution appends
// records in no order (an atomic count), the host reads them by (round, particle).
#include <cub/cub.cuh>

#include "gpu_common.cuh"
#include "gpu_launch.h"

namespace corebox::gpu {
namespace {

constexpr int kParticleBits = 31;  // particle indices are below INT32_MAX

size_t alignedBytes(size_t bytes) { return (bytes + 255) & ~size_t(255); }

size_t cubSortBytes(int64_t count) {
    size_t bytes = 0;
    cub::DeviceRadixSort::SortPairs(nullptr, bytes, static_cast<const uint64_t*>(nullptr),
                                    static_cast<uint64_t*>(nullptr), static_cast<const int32_t*>(nullptr),
                                    static_cast<int32_t*>(nullptr), int(count));
    return bytes;
}

template <class Real>
__global__ void logKeysKernel(const ImpactRecord<Real>* log, int64_t count, uint64_t* keys, int32_t* places) {
    const int64_t k = int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
    if (k >= count) return;
    keys[k] = (uint64_t(uint32_t(log[k].round)) << kParticleBits) | uint64_t(log[k].particle);
    places[k] = int32_t(k);
}

template <class Real>
__global__ void gatherLogKernel(const ImpactRecord<Real>* log, int64_t count, const int32_t* places,
                                ImpactRecord<Real>* sorted) {
    const int64_t k = int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
    if (k < count) sorted[k] = log[places[k]];
}

}  // namespace

size_t impactLogSortBytes(int64_t count) {
    const size_t n = size_t(count > 0 ? count : 0);
    return 2 * alignedBytes(n * sizeof(uint64_t)) + 2 * alignedBytes(n * sizeof(int32_t)) +
           alignedBytes(cubSortBytes(count));
}

template <class Real>
void launchSortImpactLog(const ImpactRecord<Real>* log, int64_t count, int32_t rounds, ImpactRecord<Real>* sorted,
                         void* scratch, size_t scratchBytes, cudaStream_t stream) {
    if (count <= 0) return;
    const size_t n = size_t(count);
    char* at = static_cast<char*>(scratch);
    uint64_t* keys = reinterpret_cast<uint64_t*>(at);
    uint64_t* keysOut = reinterpret_cast<uint64_t*>(at += alignedBytes(n * sizeof(uint64_t)));
    int32_t* places = reinterpret_cast<int32_t*>(at += alignedBytes(n * sizeof(uint64_t)));
    int32_t* placesOut = reinterpret_cast<int32_t*>(at += alignedBytes(n * sizeof(int32_t)));
    void* cubScratch = at += alignedBytes(n * sizeof(int32_t));
    size_t cubBytes = scratchBytes - size_t(at - static_cast<char*>(scratch));
    logKeysKernel<Real><<<blocksFor(count), kBlock, 0, stream>>>(log, count, keys, places);
    checkLaunch("log keys kernel");
    int roundBits = 1;
    while (roundBits < 32 && (int64_t(1) << roundBits) < int64_t(rounds)) ++roundBits;
    const cudaError_t e = cub::DeviceRadixSort::SortPairs(cubScratch, cubBytes, keys, keysOut, places, placesOut,
                                                          int(count), 0, kParticleBits + roundBits, stream);
    if (e != cudaSuccess) throw DeviceError(std::string("contact log sort: ") + cudaGetErrorString(e));
    gatherLogKernel<Real><<<blocksFor(count), kBlock, 0, stream>>>(log, count, placesOut, sorted);
    checkLaunch("log gather kernel");
}

#define COREBOX_INSTANTIATE(Real)                                                                                    \
    template void launchSortImpactLog<Real>(const ImpactRecord<Real>*, int64_t, int32_t, ImpactRecord<Real>*, void*, \
                                            size_t, cudaStream_t);
COREBOX_INSTANTIATE(float)
COREBOX_INSTANTIATE(double)
#undef COREBOX_INSTANTIATE

}  // namespace corebox::gpu
