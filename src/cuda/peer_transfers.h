// The four ways GPUs share data that `corebox bench p2p` times (the report's Figure 5, plus NCCL), on
// GPUs 0 .. P-1 of this host. Every device fetches the buffer of its neighbour, device (j + 1) mod P,
// at the same time; NCCL does the all-gather in which each device contributes that buffer.
//
//   DT-S  cudaMemcpyPeer, blocking: the host issues the P copies one after the other (Listing 1)
//   DT-A  cudaMemcpyPeerAsync on each device's stream, all queued at once, completion by events
//         (Listing 2)
//   DA    a kernel on the receiving device reads the neighbour's buffer in place over unified
//         addressing and writes it into local memory (Listing 3; kernels/peer_read.h)
//   NCCL  ncclAllGather of every device's buffer, in one ncclGroupStart/End, communicators from
//         ncclCommInitAll (one per device)
//
// Design note. One transfer is timed by the host clock: every device synchronised first
// (cudaDeviceSynchronize), the clock read, the transfers issued, then an event recorded after them on
// each device's stream and waited for (cudaEventSynchronize), the clock read again. So a time includes
// the host's issue cost (large for DT-S, whose copies cannot overlap) and the wait, as a simulation step
// pays them. Peer access is enabled between every device and its neighbour wherever
// cudaDeviceCanAccessPeer allows it. Where it does not, DA cannot run (refused, see refusal()) and
// cudaMemcpyPeer(Async) stage the copy through host memory by themselves (viaHost()); NCCL picks its own
// transport (NCCL_DEBUG=INFO names it). Sources hold a byte pattern per device and destinations are
// cleared before each method and size, so verify() can check that the neighbour's bytes arrived.
// CUDA and NCCL types stay in peer_transfers.cpp: the benchmark front end (src/bench) sees none.
#pragma once

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "vocabulary.h"  // Exchange

namespace corebox {

class PeerTransfers {
public:
    // Buffers on GPUs 0 .. gpus-1: a source of maxBytes and a destination of gpus * maxBytes (the
    // all-gather's output; the copies use its first part). Throws DeviceError when a device is
    // missing or the memory cannot be had (the message names the GPU and the size).
    PeerTransfers(int gpus, size_t maxBytes);
    ~PeerTransfers();
    PeerTransfers(const PeerTransfers&) = delete;
    PeerTransfers& operator=(const PeerTransfers&) = delete;

    int gpus() const;
    // cudaDeviceCanAccessPeer(reader, owner): can `reader`'s kernels read `owner`'s memory directly.
    bool canAccessPeer(int reader, int owner) const;
    // Why `method` cannot run on these GPUs (DA without peer access to a neighbour), or "" when it can.
    std::string refusal(Exchange method) const;
    // True when cudaMemcpyPeer(Async) must stage `method`'s copies through host memory (a device has no
    // peer access to its neighbour). False for DA and NCCL.
    bool viaHost(Exchange method) const;
    // Clears the destinations (not timed): call before the repeats of one method and size.
    void clearDestinations();
    // One transfer of `bytes` per device by `method`, all devices at once: the host-clock seconds from
    // the synchronisation before to the completion of every device's part. Throws DeviceError (a CUDA
    // or NCCL failure) and InputError (Exchange::Auto, or bytes over maxBytes).
    double timeOnce(Exchange method, size_t bytes);
    // After a transfer: does each device hold its neighbour's pattern (NCCL: every device's) at the
    // first and last byte of where it belongs? A few small reads, not timed.
    bool verify(Exchange method, size_t bytes);
    // "NCCL 2.27.7" once an NCCL transfer has run; "" before.
    std::string ncclVersion() const;

private:
    struct Impl;
    std::unique_ptr<Impl> m_impl;
};

}  // namespace corebox
