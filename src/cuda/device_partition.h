// How particles are spread over devices: a contiguous range [begin, end) of particle rows per
// device, each with its own stream and completion event. With one device the partition has one
// slice; several devices (and the DT-S, DT-A, DA and NCCL exchanges of the positions between them)
// reuse the same object, so multi-GPU runs add slices rather than rewrite the backend.
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
    // Even split of n rows over `devices` (CUDA ordinals); creates a stream and an event on each.
    DevicePartition(const std::vector<int>& devices, int64_t n);
    ~DevicePartition();
    DevicePartition(const DevicePartition&) = delete;
    DevicePartition& operator=(const DevicePartition&) = delete;

    void resize(int64_t n);  // new ranges, same devices and streams
    const std::vector<DeviceSlice>& slices() const { return m_slices; }
    const DeviceSlice& primary() const { return m_slices.front(); }
    void synchronize() const;

private:
    std::vector<DeviceSlice> m_slices;
};

}  // namespace corebox
