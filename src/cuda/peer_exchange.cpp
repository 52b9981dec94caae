#include "peer_exchange.h"

#include <nccl.h>

#include <mutex>
#include <set>
#include <string>
#include <utility>

#include "cuda_backend.h"
#include "cuda_check.h"
#include "errors.h"
#include "nccl_environment.h"

namespace corebox {
namespace {

void ncclCheck(ncclResult_t status, const char* what) {
    if (status != ncclSuccess) throw DeviceError(std::string(what) + ": " + ncclGetErrorString(status));
}

char* row(void* base, int64_t index, size_t rowBytes) { return static_cast<char*>(base) + size_t(index) * rowBytes; }

// Peer access is a property of the process (it outlives the backend that enabled it): enable each
// ordered pair once, rather than provoke cudaErrorPeerAccessAlreadyEnabled on every new backend.
void enablePeerAccess(int from, int to) {
    static std::mutex mutex;
    static std::set<std::pair<int, int>> enabled;
    const std::lock_guard<std::mutex> lock(mutex);
    if (!enabled.insert({from, to}).second) return;
    cudaCheck(cudaSetDevice(from), "cudaSetDevice");
    const cudaError_t status = cudaDeviceEnablePeerAccess(to, 0);
    if (status == cudaErrorPeerAccessAlreadyEnabled) cudaGetLastError();  // enabled outside corebox
    else cudaCheck(status, "cudaDeviceEnablePeerAccess");
}

// Whether GPU `from` can read GPU `to`'s memory; never where peer access is taken to be denied (tests).
bool canAccessPeer(int from, int to, bool denied) {
    if (denied) return false;
    int can = 0;
    cudaCheck(cudaDeviceCanAccessPeer(&can, from, to), "cudaDeviceCanAccessPeer");
    return can != 0;
}

}  // namespace

std::string peerAccessProblem(const std::vector<int>& devices, bool denied) {
    std::string missing;
    for (int a : devices) {
        for (int b : devices) {
            if (a == b) continue;
            if (!canAccessPeer(a, b, denied)) missing += (missing.empty() ? "" : ", ") + std::to_string(a) + " -> " + std::to_string(b);
        }
    }
    if (missing.empty()) return "";
    std::string names;
    for (int d : devices) names += (names.empty() ? "" : "; ") + std::to_string(d) + ": " + cudaDeviceDescription(d);
    return "no peer access between GPUs " + missing + " (devices " + names + ")";
}

PeerExchange::PeerExchange(const DevicePartition& partition, Exchange method, bool peerAccessDenied)
    : m_partition(partition), m_method(method) {
    if (method == Exchange::Auto) throw std::logic_error("PeerExchange: resolve Exchange::Auto first");
    std::vector<int> devices;
    for (const DeviceSlice& s : partition.slices()) devices.push_back(s.device);
    if (devices.size() > 1) {
        const std::string problem = peerAccessProblem(devices, peerAccessDenied);
        if (!problem.empty() && method == Exchange::Da)
            throw DeviceError("--exchange da reads peer memory in place and needs peer access: " + problem +
                              "; use --exchange dta, dts or nccl (they copy through host memory there)");
        for (int a : devices) {
            for (int b : devices)
                if (a != b && canAccessPeer(a, b, peerAccessDenied)) enablePeerAccess(a, b);
        }
    }
    for (int d : devices) {
        cudaCheck(cudaSetDevice(d), "cudaSetDevice");
        cudaEvent_t e = nullptr;
        cudaCheck(cudaEventCreateWithFlags(&e, cudaEventDisableTiming), "cudaEventCreate");
        m_marks.push_back(e);
    }
    if (method == Exchange::Nccl && devices.size() > 1) {
        prepareNcclEnvironment();
        std::vector<ncclComm_t> comms(devices.size());
        ncclCheck(ncclCommInitAll(comms.data(), int(devices.size()), devices.data()), "ncclCommInitAll");
        for (ncclComm_t c : comms) m_comms.push_back(c);
    }
    cudaCheck(cudaSetDevice(devices.front()), "cudaSetDevice");
}

PeerExchange::~PeerExchange() {
    for (void* c : m_comms) ncclCommDestroy(static_cast<ncclComm_t>(c));
    const auto& slices = m_partition.slices();
    for (size_t k = 0; k < m_marks.size(); ++k) {
        cudaSetDevice(slices[k].device);
        cudaEventDestroy(m_marks[k]);
    }
    if (!slices.empty()) cudaSetDevice(slices.front().device);
}

void PeerExchange::barrier() {
    const auto& slices = m_partition.slices();
    if (slices.size() < 2) return;
    for (size_t k = 0; k < slices.size(); ++k) {
        cudaCheck(cudaSetDevice(slices[k].device), "cudaSetDevice");
        cudaCheck(cudaEventRecord(m_marks[k], slices[k].stream), "cudaEventRecord");
    }
    for (size_t j = 0; j < slices.size(); ++j) {
        cudaCheck(cudaSetDevice(slices[j].device), "cudaSetDevice");
        for (size_t k = 0; k < slices.size(); ++k) {
            if (k != j) cudaCheck(cudaStreamWaitEvent(slices[j].stream, m_marks[k], 0), "cudaStreamWaitEvent");
        }
    }
    cudaCheck(cudaSetDevice(slices.front().device), "cudaSetDevice");
}

void PeerExchange::copySlice(const std::vector<void*>& buffers, size_t rowBytes, int slice, int from, int to, cudaStream_t stream) {
    const auto& slices = m_partition.slices();
    const DeviceSlice& s = slices[size_t(slice)];
    if (s.size() == 0) return;
    cudaCheck(cudaMemcpyPeerAsync(row(buffers[size_t(to)], s.begin, rowBytes), slices[size_t(to)].device,
                                  row(buffers[size_t(from)], s.begin, rowBytes), slices[size_t(from)].device, size_t(s.size()) * rowBytes,
                                  stream),
              "cudaMemcpyPeerAsync");
}

void PeerExchange::share(const std::vector<void*>& buffers, size_t rowBytes) {
    const auto& slices = m_partition.slices();
    const int p = int(slices.size());
    if (p < 2) return;
    switch (m_method) {
        case Exchange::Dts: {
            m_partition.synchronize();
            for (int step = 1; step < p; ++step) {
                for (int k = 0; k < p; ++k) {
                    const int j = (k + step) % p;
                    const DeviceSlice& s = slices[size_t(k)];
                    if (s.size() == 0) continue;
                    cudaCheck(cudaMemcpyPeer(row(buffers[size_t(j)], s.begin, rowBytes), slices[size_t(j)].device,
                                             row(buffers[size_t(k)], s.begin, rowBytes), s.device, size_t(s.size()) * rowBytes),
                              "cudaMemcpyPeer");
                }
            }
            // cudaMemcpyPeer may return before the copy lands: wait, as the report's blocking method does.
            for (const DeviceSlice& s : slices) {
                cudaCheck(cudaSetDevice(s.device), "cudaSetDevice");
                cudaCheck(cudaDeviceSynchronize(), "cudaMemcpyPeer");
            }
            cudaCheck(cudaSetDevice(slices.front().device), "cudaSetDevice");
            return;
        }
        case Exchange::Dta:
            barrier();
            for (int j = 0; j < p; ++j) {
                cudaCheck(cudaSetDevice(slices[size_t(j)].device), "cudaSetDevice");
                for (int step = 1; step < p; ++step) {
                    const int k = (j + step) % p;
                    copySlice(buffers, rowBytes, k, k, j, slices[size_t(j)].stream);
                }
            }
            barrier();  // no GPU writes its slice again (the next stage) while a peer still pulls it
            return;
        case Exchange::Da: barrier(); return;
        case Exchange::Nccl: {
            const size_t chunkBytes = size_t(m_partition.chunk()) * rowBytes;
            ncclCheck(ncclGroupStart(), "ncclGroupStart");
            for (int k = 0; k < p; ++k) {
                char* base = static_cast<char*>(buffers[size_t(k)]);
                ncclCheck(ncclAllGather(base + size_t(k) * chunkBytes, base, chunkBytes, ncclUint8, static_cast<ncclComm_t>(m_comms[size_t(k)]),
                                        slices[size_t(k)].stream),
                          "ncclAllGather");
            }
            ncclCheck(ncclGroupEnd(), "ncclGroupEnd");
            return;
        }
        case Exchange::Auto: break;
    }
}

void PeerExchange::readsDone() {
    // DT-A's closing barrier in share() already waits for its pulls; DA's force kernels read the
    // peers' positions. (The pairs-once combine reads the peers' row sums with every method; what
    // orders a GPU's next write of them after those reads is the next share(): DT-S's host wait,
    // DT-A's and DA's opening barrier, NCCL's all-gather, which completes on no GPU before every
    // GPU's part of it, queued after its combine, ran.)
    if (m_method == Exchange::Da) barrier();
}

void PeerExchange::gather(const std::vector<std::vector<void*>>& arrays, size_t rowBytes) {
    if (gpus() < 2) return;
    barrier();
    for (const std::vector<void*>& buffers : arrays)
        for (int k = 1; k < gpus(); ++k) copySlice(buffers, rowBytes, k, k, 0, m_partition.primary().stream);
    barrier();
}

void PeerExchange::scatter(const std::vector<std::vector<void*>>& arrays, size_t rowBytes) {
    if (gpus() < 2) return;
    barrier();
    for (const std::vector<void*>& buffers : arrays)
        for (int k = 1; k < gpus(); ++k) copySlice(buffers, rowBytes, k, 0, k, m_partition.primary().stream);
    barrier();
}

}  // namespace corebox
