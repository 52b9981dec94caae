// The block partials of launchBlockSums (gpu_launch.h), as a device function, so that another launch
// can take those blocks alongside its own (neighbour_list_kernels.cu: launchStageSumsAndRefresh) and
// give the same bits: each thread sums kItemsPerThread values a block apart in turn, the block's
// threads then in a fixed tree.
#pragma once

#include "gpu_common.cuh"
#include "gpu_launch.h"

namespace corebox::gpu {

constexpr int kReduceBlock = 256;
constexpr int kItemsPerThread = 8;

// Block `block` of row `row`, by a block of kReduceBlock threads (every thread calls it).
__device__ inline void blockSum(BlockSumArgs a, int block, int row) {
    __shared__ double cache[kReduceBlock];
    const char* mask = a.maskedRows >= 0 && row >= a.maskedRows ? nullptr : a.mask;  // masked: the first maskedRows rows
    const double* v = a.values + size_t(row) * size_t(a.n);
    const int64_t base = int64_t(block) * kReduceBlock * kItemsPerThread;
    double sum = 0;
    for (int k = 0; k < kItemsPerThread; ++k) {
        const int64_t i = base + int64_t(k) * kReduceBlock + threadIdx.x;
        if (i < a.n && (!mask || mask[i])) sum += v[i];
    }
    cache[threadIdx.x] = sum;
    __syncthreads();
    for (int stride = kReduceBlock / 2; stride > 0; stride /= 2) {
        if (threadIdx.x < stride) cache[threadIdx.x] += cache[threadIdx.x + stride];
        __syncthreads();
    }
    if (threadIdx.x == 0) a.partials[size_t(row) * size_t(a.blocks) + size_t(block)] = cache[0];
}

}  // namespace corebox::gpu
