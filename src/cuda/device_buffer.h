// Owning device allocation (cudaMalloc), grown on demand; contents are not kept across a resize.
#pragma once

#include <cuda_runtime_api.h>

#include <algorithm>
#include <cstddef>
#include <utility>

#include "cuda_check.h"

namespace corebox {

template <class T>
class DeviceBuffer {
public:
    DeviceBuffer() = default;
    explicit DeviceBuffer(size_t count) { resize(count); }
    ~DeviceBuffer() { release(); }
    DeviceBuffer(const DeviceBuffer&) = delete;
    DeviceBuffer& operator=(const DeviceBuffer&) = delete;
    DeviceBuffer(DeviceBuffer&& o) noexcept
        : m_data(std::exchange(o.m_data, nullptr)), m_count(std::exchange(o.m_count, 0)), m_capacity(std::exchange(o.m_capacity, 0)) {}
    DeviceBuffer& operator=(DeviceBuffer&& o) noexcept {
        if (this != &o) {
            release();
            m_data = std::exchange(o.m_data, nullptr);
            m_count = std::exchange(o.m_count, 0);
            m_capacity = std::exchange(o.m_capacity, 0);
        }
        return *this;
    }

    // At least `count` elements. A first allocation is exact; growing one takes a quarter more at
    // least, so that a count rising a few at a time (a game adding balls: every per-particle buffer
    // of the backend) does not free and allocate again each time (cudaFree waits for the device).
    void resize(size_t count) {
        if (count <= m_capacity && m_data) {
            m_count = count;
            return;
        }
        const size_t capacity = m_data ? std::max(count, m_capacity + m_capacity / 4) : count;
        release();
        void* p = nullptr;
        cudaCheck(cudaMalloc(&p, std::max<size_t>(capacity, 1) * sizeof(T)), "cudaMalloc");
        m_data = static_cast<T*>(p);
        m_count = count;
        m_capacity = capacity;
    }
    // Complete when it returns: a copy from pageable memory may still be in flight on the legacy default
    // stream, which the backends' non-blocking streams do not wait for.
    void upload(const T* host, size_t count) {
        resize(count);
        cudaCheck(cudaMemcpy(m_data, host, count * sizeof(T), cudaMemcpyHostToDevice), "upload");
        cudaCheck(cudaStreamSynchronize(cudaStreamLegacy), "upload");
    }
    void download(T* host, size_t count) const {
        cudaCheck(cudaMemcpy(host, m_data, count * sizeof(T), cudaMemcpyDeviceToHost), "download");
    }
    T* data() { return m_data; }
    const T* data() const { return m_data; }
    size_t size() const { return m_count; }

private:
    void release() {
        if (m_data) cudaFree(m_data);
        m_data = nullptr;
        m_count = m_capacity = 0;
    }
    T* m_data = nullptr;
    size_t m_count = 0;
    size_t m_capacity = 0;
};

}  // namespace corebox
