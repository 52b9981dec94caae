// How particles are spread over devices: a contiguous range [begin, end) of particle rows per
// device, each with its own stream and completion event. Slices are chunks of equal length
// ceil(n / P) (the last may be shorter, or empty when n < P): an NCCL all-gather moves equal
// chunks, so full-length arrays have paddedRows() = P x chunk rows. With one device the partition
// has one slice and no padding.
#pragma once

#include <cuda_runtime_api.h>

#include <cstdint>
#include <vector>

namespace corebox {

struct DeviceSlice {
    int device = 0;
    int64_t begin = 0, end = 0;
    cudaStream_t stream = nullptr;
    cudaEvent_t done = nullptr;
    int64_t size() const { return end - begin; }
};

class DevicePartition {
public:
    // Chunks of n rows over `devices` (CUDA ordinals); creates a stream and an event on each.
    DevicePartition(const std::vector<int>& devices, int64_t n);
    ~DevicePartition();
    DevicePartition(const DevicePartition&) = delete;
    DevicePartition& operator=(const DevicePartition&) = delete;

    void resize(int64_t n);  // new ranges, same devices and streams
    const std::vector<DeviceSlice>& slices() const { return m_slices; }
    const DeviceSlice& primary() const { return m_slices.front(); }
    int64_t chunk() const { return m_chunk; }
    int64_t paddedRows() const { return m_chunk * int64_t(m_slices.size()); }
    void synchronize() const;

private:
    std::vector<DeviceSlice> m_slices;
    int64_t m_chunk = 0;
};

}  // namespace corebox
