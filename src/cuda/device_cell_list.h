// The cell list on a device (kernels/cell_list.h, built by kernels/cell_list_kernels.cu): owns the
// sort's buffers and rebuilds them from positions on a stream. The view it returns is what the
// contact search (and later the neighbour lists of cut-off forces) walk.
#pragma once

#include <cuda_runtime_api.h>

#include "device_buffer.h"
#include "gpu_launch.h"

namespace corebox {

template <class Real>
class DeviceCellList {
public:
    // Enqueues the build of n positions x (device memory) with `geometry` on `stream`; the view's
    // arrays are valid once the stream reaches this point, until the next build.
    CellListView build(const Vec3<Real>* x, int64_t n, const CellGeometry& geometry, cudaStream_t stream) {
        return build(x, n, geometry, CellSplit<Real>{}, 0.0, stream);
    }
    // The same, keeping the particles `split` names (device pointers) out of the cells; gridRadius: the
    // largest radius left in them (chooseCellSplit).
    CellListView build(const Vec3<Real>* x, int64_t n, const CellGeometry& geometry, const CellSplit<Real>& split, double gridRadius,
                       cudaStream_t stream) {
        m_keys.resize(size_t(n));
        m_sortedKeys.resize(size_t(n));
        m_indices.resize(size_t(n));
        m_sorted.resize(size_t(n));
        m_cellStart.resize(size_t(geometry.cellCount()) + 1);
        gpu::CellListArgs<Real> a{};
        a.x = x;
        a.n = n;
        a.geometry = geometry;
        a.cellStart = m_cellStart.data();
        a.sorted = m_sorted.data();
        a.keys = m_keys.data();
        a.sortedKeys = m_sortedKeys.data();
        a.indices = m_indices.data();
        a.scratchBytes = gpu::cellListScratchBytes(n);
        m_scratch.resize(a.scratchBytes);
        a.scratch = m_scratch.data();
        a.split = split;
        a.gridRadius = gridRadius;
        gpu::launchBuildCellList(a, stream);
        return a.view();
    }

private:
    DeviceBuffer<int32_t> m_cellStart, m_sorted, m_indices;
    DeviceBuffer<uint32_t> m_keys, m_sortedKeys;
    DeviceBuffer<unsigned char> m_scratch;
};

}  // namespace corebox
