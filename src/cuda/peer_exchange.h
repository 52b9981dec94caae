// How GPUs share particle rows (DESIGN.md sec. 4; the report's sec. 5). Each GPU holds a full-length
// copy of a row array (positions) whose own slice it wrote; before a force pass every GPU needs every
// slice. The four methods:
//   DT-S  the report's Listing 1: the host waits for every GPU, then blocking cudaMemcpyPeer calls
//         in ring order (GPU k sends to k+1, k+2, ...), then waits for the copies to land.
//   DT-A  its Listing 2: each GPU pulls every other slice with cudaMemcpyPeerAsync on its own stream,
//         ordered after the writers by events; no host wait.
//   DA    its Listing 3: nothing moves; the force kernel reads the other slices in place over
//         unified addressing (ForceArgs::peers), ordered after the writers by events.
//   NCCL  ncclAllGather in place, one group over one communicator per GPU (ncclCommInitAll).
// Ordering without host waits (DT-A, DA): barrier() makes every GPU's stream wait for the work queued
// so far on every other stream (one event per GPU). share() opens with one, so no slice is read
// before its GPU wrote it; a second one closes the pass (DT-A: after the pulls, in share(); DA:
// after the force kernels, in readsDone()), so no GPU overwrites its slice while a peer still reads
// it. NCCL orders itself; DT-S waits on the host.
// Peer access is enabled between every pair that has it. Without it DA is refused (DeviceError) and
// the copies go through host memory (the CUDA runtime does that for cudaMemcpyPeer[Async]).
// gather() and scatter() move slices to and from the home GPU (the first) by peer copies on its
// stream, whatever the method: they serve the collision stage and output, not the force passes.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "device_partition.h"
#include "vocabulary.h"

namespace corebox {

class PeerExchange {
public:
    // `method` must not be Auto. Throws DeviceError when DA lacks peer access or NCCL fails.
    // peerAccessDenied (tests only, CudaBackendOptions::peerAccessDenied): every pair taken to have none.
    PeerExchange(const DevicePartition& partition, Exchange method, bool peerAccessDenied = false);
    ~PeerExchange();
    PeerExchange(const PeerExchange&) = delete;
    PeerExchange& operator=(const PeerExchange&) = delete;

    Exchange method() const { return m_method; }
    int gpus() const { return int(m_partition.slices().size()); }

    // buffers[k]: GPU k's full-length array of rows of rowBytes bytes. After share(), rows of slice k
    // in buffers[j] equal those in buffers[k] for every j (DA: readable in place instead).
    void share(const std::vector<void*>& buffers, size_t rowBytes);
    // After the kernels that read the shared rows.
    void readsDone();
    // For each array (buffers per GPU as in share): slice k of buffers[k] into buffers[0] for every
    // k > 0; or slice k of buffers[0] into buffers[k].
    void gather(const std::vector<std::vector<void*>>& arrays, size_t rowBytes);
    void scatter(const std::vector<std::vector<void*>>& arrays, size_t rowBytes);
    // Every stream waits for what every other stream has queued so far.
    void barrier();

private:
    // Rows of slice `slice` from buffers[from] to buffers[to], on `stream`.
    void copySlice(const std::vector<void*>& buffers, size_t rowBytes, int slice, int from, int to, cudaStream_t stream);

    const DevicePartition& m_partition;
    Exchange m_method;
    std::vector<cudaEvent_t> m_marks;  // one per GPU, for barrier()
    std::vector<void*> m_comms;        // ncclComm_t per GPU (NCCL only)
};

// Which GPUs can read each other's memory, and a message naming those that cannot ("" when all can);
// denied: every pair taken to have no peer access (tests of that path on machines whose GPUs have it).
std::string peerAccessProblem(const std::vector<int>& devices, bool denied = false);

}  // namespace corebox
