#include "device_partition.h"

#include <algorithm>

#include "cuda_check.h"

namespace corebox {

DevicePartition::DevicePartition(const std::vector<int>& devices, int64_t n) {
    for (int device : devices) {
        DeviceSlice slice;
        slice.device = device;
        cudaCheck(cudaSetDevice(device), "cudaSetDevice");
        cudaCheck(cudaStreamCreateWithFlags(&slice.stream, cudaStreamNonBlocking), "cudaStreamCreate");
        cudaCheck(cudaEventCreateWithFlags(&slice.done, cudaEventDisableTiming), "cudaEventCreate");
        m_slices.push_back(slice);
    }
    cudaCheck(cudaSetDevice(devices.front()), "cudaSetDevice");
    resize(n);
}

DevicePartition::~DevicePartition() {
    for (DeviceSlice& s : m_slices) {
        cudaSetDevice(s.device);
        cudaEventDestroy(s.done);
        cudaStreamDestroy(s.stream);
    }
    if (!m_slices.empty()) cudaSetDevice(m_slices.front().device);
}

void DevicePartition::resize(int64_t n) {
    const int64_t count = int64_t(m_slices.size());
    m_chunk = (n + count - 1) / count;
    for (int64_t k = 0; k < count; ++k) {
        m_slices[size_t(k)].begin = std::min(n, m_chunk * k);
        m_slices[size_t(k)].end = std::min(n, m_chunk * (k + 1));
    }
}

void DevicePartition::synchronize() const {
    for (const DeviceSlice& s : m_slices) cudaCheck(cudaStreamSynchronize(s.stream), "kernel execution");
}

}  // namespace corebox
