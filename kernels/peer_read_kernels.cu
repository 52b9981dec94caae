// The direct-access copy of kernels/peer_read.h: a grid-stride loop of 16-byte loads from the peer.
#include <cstdint>

#include "gpu_common.cuh"
#include "peer_read.h"

namespace corebox::gpu {
namespace {

// Enough blocks to fill every SM of an H200 (132 SMs x 8 blocks of 256 threads) several times over;
// the grid-stride loop covers any size with it, and more blocks only add scheduling work.
constexpr unsigned int kMaxPeerReadBlocks = 4096;

__global__ void peerReadWords(const uint4* __restrict__ source, uint4* __restrict__ destination, size_t words) {
    const size_t stride = size_t(gridDim.x) * blockDim.x;
    for (size_t i = size_t(blockIdx.x) * blockDim.x + threadIdx.x; i < words; i += stride) destination[i] = source[i];
}

// The bytes after the last whole 16-byte word (none for the benchmark's sizes; kept for any caller).
__global__ void peerReadTail(const unsigned char* source, unsigned char* destination, size_t bytes) {
    const size_t i = size_t(blockIdx.x) * blockDim.x + threadIdx.x;
    if (i < bytes) destination[i] = source[i];
}

}  // namespace

void launchPeerRead(const PeerReadArgs& args, cudaStream_t stream) {
    const bool aligned = reinterpret_cast<uintptr_t>(args.source) % sizeof(uint4) == 0 &&
                         reinterpret_cast<uintptr_t>(args.destination) % sizeof(uint4) == 0;
    const size_t words = aligned ? args.bytes / sizeof(uint4) : 0;
    if (words > 0) {
        const size_t wanted = (words + kBlock - 1) / kBlock;
        const unsigned int blocks = unsigned(wanted < kMaxPeerReadBlocks ? wanted : kMaxPeerReadBlocks);
        peerReadWords<<<blocks, kBlock, 0, stream>>>(static_cast<const uint4*>(args.source),
                                                     static_cast<uint4*>(args.destination), words);
        checkLaunch("peer read kernel");
    }
    const size_t done = words * sizeof(uint4);
    const size_t tail = args.bytes - done;
    if (tail > 0) {
        // Byte by byte: only misaligned or odd-sized buffers come here, never the benchmark's.
        peerReadTail<<<blocksFor(int64_t(tail)), kBlock, 0, stream>>>(
            static_cast<const unsigned char*>(args.source) + done, static_cast<unsigned char*>(args.destination) + done,
            tail);
        checkLaunch("peer read kernel (tail)");
    }
}

}  // namespace corebox::gpu
