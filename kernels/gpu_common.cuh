// Small helpers shared by the .cu files: launch geometry and error checks after launches.
#pragma once

#include <cuda_runtime.h>

#include <algorithm>
#include <cstdint>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include "gpu_launch.h"
#include "errors.h"  // DeviceError: a failed launch is a device error (exit code 4), like any CUDA failure

namespace corebox::gpu {

constexpr int kBlock = 256;

inline unsigned int blocksFor(int64_t n, int block = kBlock) { return unsigned((n + block - 1) / block); }

// Multiprocessors of the current device, asked once per process (launch geometry: enough blocks to
// fill them). The GPUs one process uses are of one model.
inline int multiprocessorCount() {
    static const int count = [] {
        int device = 0, sms = 0;
        cudaGetDevice(&device);
        cudaDeviceGetAttribute(&sms, cudaDevAttrMultiProcessorCount, device);
        return sms > 0 ? sms : 1;
    }();
    return count;
}

// L2 bytes of the current device, asked once per process.
inline size_t l2CacheBytes() {
    static const size_t bytes = [] {
        int device = 0, l2 = 0;
        cudaGetDevice(&device);
        cudaDeviceGetAttribute(&l2, cudaDevAttrL2CacheSize, device);
        return size_t(l2 > 0 ? l2 : 0);
    }();
    return bytes;
}

// Blocks of kBlock threads of `kernel` that can be resident at once on the current device (what a
// cooperative launch may use), 0 where the device has no cooperative launch.
template <class Kernel>
int cooperativeResidentBlocks(Kernel kernel) {
    int device = 0, supported = 0, blocks = 0;
    cudaGetDevice(&device);
    cudaDeviceGetAttribute(&supported, cudaDevAttrCooperativeLaunch, device);
    if (!supported) return 0;
    cudaOccupancyMaxActiveBlocksPerMultiprocessor(&blocks, kernel, kBlock, 0);
    return blocks * multiprocessorCount();
}

// Blocks of kBlock threads of `kernel` resident at once on the current device (at least one): a grid that
// fits at once and strides its work.
template <class Kernel>
int residentBlocks(Kernel kernel) {
    int blocks = 0;
    cudaOccupancyMaxActiveBlocksPerMultiprocessor(&blocks, kernel, kBlock, 0);
    return std::max(blocks, 1) * multiprocessorCount();
}

// The row starts of a block's kBlock consecutive particles from `first` (starts[k] = rowStart[first + k],
// particles + 1 of them, in shared memory), for kernels that take the block's rows a thread a row; returns
// how many particles the block has. Every thread of the block calls it (a barrier).
__device__ inline int stageRowStarts(int64_t* starts, const int64_t* rowStart, int64_t first, int64_t n) {
    const int particles = int(n - first < int64_t(kBlock) ? n - first : int64_t(kBlock));
    for (int k = int(threadIdx.x); k <= particles; k += kBlock) starts[k] = rowStart[first + k];
    __syncthreads();
    return particles;
}

// The particle (0 .. particles - 1) whose rows [starts[k], starts[k + 1]) hold row s: the last one whose
// rows begin at or before s (particles with no rows in between are passed over).
__device__ inline int particleOfRow(const int64_t* starts, int particles, int64_t s) {
    int lo = 0, hi = particles - 1;
    while (lo < hi) {
        const int mid = (lo + hi + 1) / 2;
        if (starts[mid] <= s)
            lo = mid;
        else
            hi = mid - 1;
    }
    return lo;
}

// atomicAdd(counter, 1) for each calling thread, one atomic a warp: the threads that call together
// share it and each gets its own slot (in lane order within the warp's block of slots). Thousands of
// threads on one address queue behind each other otherwise.
__device__ inline unsigned int warpAggregatedIncrement(unsigned int* counter) {
    const unsigned int together = __activemask();
    const int lane = int(threadIdx.x % 32);
    const int leader = __ffs(int(together)) - 1;
    unsigned int base = 0;
    if (lane == leader) base = atomicAdd(counter, unsigned(__popc(together)));
    base = __shfl_sync(together, base, leader);
    return base + unsigned(__popc(together & ((1u << lane) - 1u)));
}

// atomicAdd(total, value) for each calling thread, one atomic a warp: the threads that call together add
// their sum (each value below 2^32 / 32). A sum of integers: the same in any order.
__device__ inline void warpAggregatedAdd(unsigned long long* total, unsigned int value) {
    const unsigned int together = __activemask();
    const unsigned int sum = __reduce_add_sync(together, value);
    if (int(threadIdx.x % 32) == __ffs(int(together)) - 1 && sum > 0u) atomicAdd(total, (unsigned long long)sum);
}

// StageGate (gpu_launch.h): whether a gated launch does its work.
__device__ inline bool gateOpen(const StageGate& g) {
    const bool open = g.runAheadOf ? runAheadOpen(*g.runAheadOf, g.freshLists) : !g.stage || ((g.stages >> *g.stage) & 1u) != 0u;
    return open && (!g.clear || *g.clear == 0u);
}

// Programmatic dependent launch (compute capability 9.0 on): a kernel launched by launchDependent may be
// scheduled while the kernel before it on the stream is still ending, its launch latency hidden behind that
// kernel's tail. Such a kernel calls waitForPrimary() before it reads or writes anything: that waits until
// the kernel before has finished and its writes are visible, so the results are those of plain stream
// order. In a kernel launched the usual way it returns at once.
__device__ inline void waitForPrimary() {
#if defined(__CUDA_ARCH__) && __CUDA_ARCH__ >= 900
    cudaGridDependencySynchronize();
#endif
}

// Whether `kernel`, as it runs on the current device, was compiled for compute capability 9.0 or later,
// and so with its waitForPrimary: asked once per kernel and device. Not the device's capability alone: a
// build for older architectures runs on a newer device as PTX compiled without the wait.
inline bool waitsForPrimary(const void* kernel) {
    struct Known {
        const void* kernel;
        int device;
        bool waits;
    };
    static std::mutex mutex;
    static std::vector<Known> known;
    int device = 0;
    cudaGetDevice(&device);
    const std::lock_guard<std::mutex> lock(mutex);
    for (const Known& k : known)
        if (k.kernel == kernel && k.device == device) return k.waits;
    cudaFuncAttributes attributes{};
    const bool waits = cudaFuncGetAttributes(&attributes, kernel) == cudaSuccess && attributes.ptxVersion >= 90;
    known.push_back(Known{kernel, device, waits});
    return waits;
}

// kernel<<<blocks, kBlock, 0, stream>>>(args...), as a programmatic dependent launch where the kernel
// waits for it (it must begin with waitForPrimary()); `what` names it in errors.
template <class... Params, class... Args>
void launchDependent(void (*kernel)(Params...), unsigned int blocks, cudaStream_t stream, const char* what,
                     Args&&... args) {
    cudaLaunchConfig_t config{};
    config.gridDim = dim3(blocks);
    config.blockDim = dim3(kBlock);
    config.dynamicSmemBytes = 0;
    config.stream = stream;
    cudaLaunchAttribute attribute[1];
    attribute[0].id = cudaLaunchAttributeProgrammaticStreamSerialization;
    attribute[0].val.programmaticStreamSerializationAllowed =
        waitsForPrimary(reinterpret_cast<const void*>(kernel)) ? 1 : 0;
    config.attrs = attribute;
    config.numAttrs = 1;
    const cudaError_t e = cudaLaunchKernelEx(&config, kernel, std::forward<Args>(args)...);
    if (e != cudaSuccess) {
        (void)cudaGetLastError();  // reported here, not again by a later launch's check
        throw DeviceError(std::string(what) + ": " + cudaGetErrorString(e));
    }
}

// Launch errors (bad configuration) surface at once; asynchronous faults at the next sync, where
// the host side (src/cuda) checks them.
inline void checkLaunch(const char* what) {
    const cudaError_t e = cudaGetLastError();
    if (e != cudaSuccess) throw DeviceError(std::string(what) + ": " + cudaGetErrorString(e));
}

}  // namespace corebox::gpu
