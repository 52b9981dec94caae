// Page-locked host memory (cudaMallocHost), grown on demand, for the small results a step reads back
// (event counts, block partial sums, residuals). A copy into pageable memory is staged by the driver
// and costs several microseconds more per read-back; at small N a step is made of such read-backs.
#pragma once

#include <cuda_runtime_api.h>

#include <algorithm>
#include <cstddef>

#include "cuda_check.h"

namespace corebox {

template <class T>
class PinnedBuffer {
public:
    PinnedBuffer() = default;
    ~PinnedBuffer() {
        if (m_data) cudaFreeHost(m_data);
    }
    PinnedBuffer(const PinnedBuffer&) = delete;
    PinnedBuffer& operator=(const PinnedBuffer&) = delete;

    // At least `count` elements; contents are not kept across a growth. Growth is by half again at
    // least: cudaFreeHost waits for the device, and a state read (readState) grows with every add.
    T* resize(size_t count) {
        if (count > m_capacity || !m_data) {
            if (m_data) cudaFreeHost(m_data);
            m_data = nullptr;
            const size_t capacity = std::max<size_t>({count, 16, m_capacity + m_capacity / 2});
            void* p = nullptr;
            cudaCheck(cudaMallocHost(&p, capacity * sizeof(T)), "cudaMallocHost");
            m_data = static_cast<T*>(p);
            m_capacity = capacity;
        }
        return m_data;
    }
    T* data() { return m_data; }
    const T* data() const { return m_data; }

private:
    T* m_data = nullptr;
    size_t m_capacity = 0;
};

}  // namespace corebox
