// Direct access (the report's DA, Listing 3) as `corebox bench p2p` measures it: a kernel on one GPU
// reads a buffer that lives on another GPU in place, over unified virtual addressing with peer access
// enabled, and writes it into its own memory. Host-callable; the kernel is in peer_read_kernels.cu.
//
// Design note. The copy is what a force kernel does with a peer's positions under DA, stripped of the
// arithmetic: every byte crosses the link once, as loads issued by the reading device's threads. It
// moves 16-byte words, the widest load one thread issues, where the pointers allow (cudaMalloc gives
// 256-byte alignment and the benchmark's sizes are multiples of 4 KiB).
#pragma once

#include <cuda_runtime_api.h>

#include <cstddef>

namespace corebox::gpu {

struct PeerReadArgs {
    const void* source;  // on the peer device (a UVA pointer); read only
    void* destination;   // on the device the kernel runs on
    size_t bytes;
};

// Queues the read on `stream`, which belongs to the current device (the destination's). Peer access
// to the source's device must be enabled (cudaDeviceEnablePeerAccess) before.
void launchPeerRead(const PeerReadArgs& args, cudaStream_t stream);

}  // namespace corebox::gpu
