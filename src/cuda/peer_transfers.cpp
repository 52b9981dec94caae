#include "peer_transfers.h"

#include <cuda_runtime_api.h>
#include <nccl.h>

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "cuda_check.h"
#include "errors.h"
#include "nccl_environment.h"
#include "peer_read.h"

namespace corebox {
namespace {

void ncclCheck(ncclResult_t status, const char* what) {
    if (status != ncclSuccess) throw DeviceError(std::string(what) + ": " + ncclGetErrorString(status));
}

std::string gpuName(int ordinal) { return "GPU " + std::to_string(ordinal); }

std::string sizeText(size_t bytes) {
    char text[64];
    std::snprintf(text, sizeof text, "%zu bytes (%.3g GiB)", bytes, double(bytes) / double(size_t(1) << 30));
    return text;
}

// The byte every element of device d's source holds: distinct for up to 255 devices, never 0 (the
// cleared destination).
unsigned char patternOf(int device) { return static_cast<unsigned char>(1 + device % 255); }

}  // namespace

struct PeerTransfers::Impl {
    struct Device {
        int ordinal = 0;
        cudaStream_t stream = nullptr;
        cudaEvent_t done = nullptr;
        void* source = nullptr;       // maxBytes, filled with patternOf(ordinal)
        void* destination = nullptr;  // gpus * maxBytes
    };
    std::vector<Device> devices;
    std::vector<std::vector<bool>> access;  // access[reader][owner]
    size_t maxBytes = 0;
    std::vector<ncclComm_t> comms;  // made on the first NCCL transfer
    std::string ncclVersion;

    Impl() = default;
    Impl(const Impl&) = delete;
    Impl& operator=(const Impl&) = delete;
    // Here rather than in ~PeerTransfers, so that a constructor that throws half way frees what it made.
    // Teardown errors are ignored: a destructor cannot report them, and a failed run has said why.
    ~Impl() {
        for (ncclComm_t c : comms) {
            if (c) ncclCommDestroy(c);
        }
        for (Device& d : devices) {
            cudaSetDevice(d.ordinal);
            if (d.source) cudaFree(d.source);
            if (d.destination) cudaFree(d.destination);
            if (d.done) cudaEventDestroy(d.done);
            if (d.stream) cudaStreamDestroy(d.stream);
        }
    }

    int neighbour(int d) const { return (d + 1) % int(devices.size()); }

    void synchronizeAll() {
        for (const Device& d : devices) {
            cudaCheck(cudaSetDevice(d.ordinal), "cudaSetDevice");
            cudaCheck(cudaDeviceSynchronize(), "cudaDeviceSynchronize");
        }
    }

    // Completion of what each device's stream holds (and, through the legacy default stream's
    // ordering, of DT-S's blocking copies): one event per device, recorded, then waited for.
    void waitAll() {
        for (const Device& d : devices) {
            cudaCheck(cudaSetDevice(d.ordinal), "cudaSetDevice");
            cudaCheck(cudaEventRecord(d.done, d.stream), "cudaEventRecord");
        }
        for (const Device& d : devices) cudaCheck(cudaEventSynchronize(d.done), "cudaEventSynchronize");
    }

    void makeCommunicators() {
        if (!comms.empty()) return;
        prepareNcclEnvironment();  // before the first NCCL call of the process
        std::vector<int> ordinals;
        for (const Device& d : devices) ordinals.push_back(d.ordinal);
        comms.assign(devices.size(), nullptr);
        ncclCheck(ncclCommInitAll(comms.data(), int(devices.size()), ordinals.data()), "ncclCommInitAll");
        int version = 0;
        ncclCheck(ncclGetVersion(&version), "ncclGetVersion");
        ncclVersion = "NCCL " + std::to_string(version / 10000) + "." + std::to_string(version % 10000 / 100) + "." +
                      std::to_string(version % 100);
    }

    void issue(Exchange method, size_t bytes) {
        const int p = int(devices.size());
        switch (method) {
            case Exchange::Dts:
                // Listing 1 with t = 1: each call returns when its copy is done, so the P copies run one
                // after the other, never together.
                for (int j = 0; j < p; ++j) {
                    const Device& to = devices[size_t(j)];
                    const Device& from = devices[size_t(neighbour(j))];
                    cudaCheck(cudaSetDevice(to.ordinal), "cudaSetDevice");
                    cudaCheck(cudaMemcpyPeer(to.destination, to.ordinal, from.source, from.ordinal, bytes),
                              "cudaMemcpyPeer");
                }
                break;
            case Exchange::Dta:
                for (int j = 0; j < p; ++j) {
                    const Device& to = devices[size_t(j)];
                    const Device& from = devices[size_t(neighbour(j))];
                    cudaCheck(cudaSetDevice(to.ordinal), "cudaSetDevice");
                    cudaCheck(
                        cudaMemcpyPeerAsync(to.destination, to.ordinal, from.source, from.ordinal, bytes, to.stream),
                        "cudaMemcpyPeerAsync");
                }
                break;
            case Exchange::Da:
                for (int j = 0; j < p; ++j) {
                    const Device& to = devices[size_t(j)];
                    const Device& from = devices[size_t(neighbour(j))];
                    cudaCheck(cudaSetDevice(to.ordinal), "cudaSetDevice");
                    gpu::launchPeerRead(gpu::PeerReadArgs{from.source, to.destination, bytes}, to.stream);
                }
                break;
            case Exchange::Nccl:
                makeCommunicators();
                ncclCheck(ncclGroupStart(), "ncclGroupStart");
                for (int j = 0; j < p; ++j) {
                    const Device& d = devices[size_t(j)];
                    ncclCheck(ncclAllGather(d.source, d.destination, bytes, ncclUint8, comms[size_t(j)], d.stream),
                              "ncclAllGather");
                }
                ncclCheck(ncclGroupEnd(), "ncclGroupEnd");
                break;
            case Exchange::Auto:
                throw InputError("bench p2p: 'auto' is not a transfer method; name one of dts, dta, da, nccl");
        }
    }

    // The first and last byte of [offset, offset + bytes) of device d's destination.
    bool holds(const Device& d, size_t offset, size_t bytes, unsigned char expected) {
        unsigned char ends[2] = {0, 0};
        cudaCheck(cudaSetDevice(d.ordinal), "cudaSetDevice");
        const unsigned char* base = static_cast<const unsigned char*>(d.destination) + offset;
        cudaCheck(cudaMemcpy(&ends[0], base, 1, cudaMemcpyDeviceToHost), "verify read");
        cudaCheck(cudaMemcpy(&ends[1], base + bytes - 1, 1, cudaMemcpyDeviceToHost), "verify read");
        return ends[0] == expected && ends[1] == expected;
    }
};

PeerTransfers::PeerTransfers(int gpus, size_t maxBytes) : m_impl(std::make_unique<Impl>()) {
    int count = 0;
    if (cudaGetDeviceCount(&count) != cudaSuccess) {
        cudaGetLastError();
        count = 0;
    }
    if (gpus < 2 || gpus > count) {
        throw DeviceError("peer transfers need 2 or more GPUs; asked for " + std::to_string(gpus) + ", found " +
                          std::to_string(count));
    }
    Impl& m = *m_impl;
    m.maxBytes = maxBytes;
    m.devices.resize(size_t(gpus));
    m.access.assign(size_t(gpus), std::vector<bool>(size_t(gpus), false));
    for (int r = 0; r < gpus; ++r) {
        for (int o = 0; o < gpus; ++o) {
            int can = 0;
            if (r != o) cudaCheck(cudaDeviceCanAccessPeer(&can, r, o), "cudaDeviceCanAccessPeer");
            m.access[size_t(r)][size_t(o)] = can != 0;
        }
    }
    for (int j = 0; j < gpus; ++j) {
        Impl::Device& d = m.devices[size_t(j)];
        d.ordinal = j;
        cudaCheck(cudaSetDevice(j), "cudaSetDevice");
        const int next = m.neighbour(j);
        if (m.access[size_t(j)][size_t(next)]) {
            const cudaError_t e = cudaDeviceEnablePeerAccess(next, 0);
            if (e == cudaErrorPeerAccessAlreadyEnabled) {
                cudaGetLastError();  // P = 2: both neighbours are the same pair, enabled once per direction
            } else {
                cudaCheck(e, "cudaDeviceEnablePeerAccess");
            }
        }
        cudaCheck(cudaStreamCreate(&d.stream), "cudaStreamCreate");
        cudaCheck(cudaEventCreateWithFlags(&d.done, cudaEventDisableTiming), "cudaEventCreate");
        const size_t gathered = size_t(gpus) * maxBytes;
        if (cudaMalloc(&d.source, maxBytes) != cudaSuccess || cudaMalloc(&d.destination, gathered) != cudaSuccess) {
            cudaGetLastError();
            throw DeviceError("cannot allocate " + sizeText(maxBytes + gathered) + " on " + gpuName(j) +
                              " (a source and the all-gather's destination of " + std::to_string(gpus) +
                              " x the largest size); use a smaller --max-bytes");
        }
        cudaCheck(cudaMemset(d.source, patternOf(j), maxBytes), "cudaMemset");
    }
    m.synchronizeAll();
}

PeerTransfers::~PeerTransfers() = default;

int PeerTransfers::gpus() const { return int(m_impl->devices.size()); }

bool PeerTransfers::canAccessPeer(int reader, int owner) const { return m_impl->access[size_t(reader)][size_t(owner)]; }

std::string PeerTransfers::refusal(Exchange method) const {
    if (method != Exchange::Da) return "";
    for (int j = 0; j < gpus(); ++j) {
        const int next = m_impl->neighbour(j);
        if (!canAccessPeer(j, next)) {
            return "DA needs peer access, and " + gpuName(j) + " cannot read " + gpuName(next) +
                   "'s memory (cudaDeviceCanAccessPeer: no; no NVLink or PCIe peer path between them); "
                   "DT-S and DT-A still run there, through host memory";
        }
    }
    return "";
}

bool PeerTransfers::viaHost(Exchange method) const {
    if (method != Exchange::Dts && method != Exchange::Dta) return false;
    for (int j = 0; j < gpus(); ++j) {
        if (!canAccessPeer(j, m_impl->neighbour(j))) return true;
    }
    return false;
}

void PeerTransfers::clearDestinations() {
    for (const Impl::Device& d : m_impl->devices) {
        cudaCheck(cudaSetDevice(d.ordinal), "cudaSetDevice");
        cudaCheck(cudaMemset(d.destination, 0, size_t(gpus()) * m_impl->maxBytes), "cudaMemset");
    }
    m_impl->synchronizeAll();
}

double PeerTransfers::timeOnce(Exchange method, size_t bytes) {
    if (bytes == 0 || bytes > m_impl->maxBytes) {
        throw InputError("bench p2p: transfer of " + std::to_string(bytes) + " bytes outside (0, " +
                         std::to_string(m_impl->maxBytes) + "]");
    }
    const std::string why = refusal(method);
    if (!why.empty()) throw DeviceError(why);
    using Clock = std::chrono::steady_clock;
    // Communicators are made once, outside the clock: ncclCommInitAll costs a second or more, which no
    // transfer pays.
    if (method == Exchange::Nccl) m_impl->makeCommunicators();
    m_impl->synchronizeAll();
    const Clock::time_point start = Clock::now();
    m_impl->issue(method, bytes);
    m_impl->waitAll();
    return std::chrono::duration<double>(Clock::now() - start).count();
}

bool PeerTransfers::verify(Exchange method, size_t bytes) {
    Impl& m = *m_impl;
    bool ok = true;
    for (int j = 0; j < gpus(); ++j) {
        const Impl::Device& d = m.devices[size_t(j)];
        if (method == Exchange::Nccl) {
            // The all-gather puts device k's buffer at k * bytes on every device.
            for (int k = 0; k < gpus(); ++k) ok = ok && m.holds(d, size_t(k) * bytes, bytes, patternOf(k));
        } else {
            ok = ok && m.holds(d, 0, bytes, patternOf(m.neighbour(j)));
        }
    }
    return ok;
}

std::string PeerTransfers::ncclVersion() const { return m_impl->ncclVersion; }

}  // namespace corebox
