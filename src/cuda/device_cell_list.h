// The cell list on a device (kernels/cell_list.h, built by kernels/cell_list_kernels.cu): owns the
// sort's buffers and rebuilds them from positions on a stream. The view it returns is what the
// contact search (and later the neighbour lists of cut-off forces) walk.
#pragma once

#include <cuda_runtime_api.h>

#include <exception>
#include <utility>
#include <string>

#include "device_buffer.h"
#include "cuda_check.h"
#include "gpu_launch.h"

namespace corebox {

template <class Real>
class DeviceCellList {
public:
    DeviceCellList() = default;
    DeviceCellList(const DeviceCellList&) = delete;
    DeviceCellList& operator=(const DeviceCellList&) = delete;
    ~DeviceCellList() { forgetGraph(); }

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
        if (n != m_scratchFor) {  // a query of CUB's: host time
            m_scratchBytes = gpu::cellListScratchBytes(n);
            m_scratchFor = n;
        }
        m_scratch.resize(m_scratchBytes);
        gpu::CellListArgs<Real> a{};
        a.x = x;
        a.n = n;
        a.geometry = geometry;
        a.cellStart = m_cellStart.data();
        a.sorted = m_sorted.data();
        a.keys = m_keys.data();
        a.sortedKeys = m_sortedKeys.data();
        a.indices = m_indices.data();
        a.scratchBytes = m_scratchBytes;
        a.scratch = m_scratch.data();
        a.split = split;
        a.gridRadius = gridRadius;
        launch(a, stream);
        return a.view();
    }

    // Buffers and the captured build travel together (the graph's arguments are these buffers).
    friend void swap(DeviceCellList& a, DeviceCellList& b) noexcept {
        using std::swap;
        swap(a.m_cellStart, b.m_cellStart);
        swap(a.m_sorted, b.m_sorted);
        swap(a.m_indices, b.m_indices);
        swap(a.m_keys, b.m_keys);
        swap(a.m_sortedKeys, b.m_sortedKeys);
        swap(a.m_scratch, b.m_scratch);
        swap(a.m_scratchFor, b.m_scratchFor);
        swap(a.m_scratchBytes, b.m_scratchBytes);
        swap(a.m_exec, b.m_exec);
        swap(a.m_built, b.m_built);
        swap(a.m_builtOn, b.m_builtOn);
        swap(a.m_graphsOff, b.m_graphsOff);
    }

private:
    // A build of more than one block's particles is several launches (keys, the radix sort's passes,
    // the cell starts) whose host side, CUB's most of all, cost a collision round about 35 us (an H200's
    // host, 10^5 particles, 37 of a round's 44 us of enqueueing). So they are captured into a graph once
    // and the graph is launched while the build's arguments stay the same; a change of positions'
    // buffer, count, geometry or split captures again. Not on the legacy default stream (no capture
    // there) nor for builds of one launch.
    void launch(const gpu::CellListArgs<Real>& a, cudaStream_t stream) {
        if (stream == nullptr || a.n <= kOneLaunchBuild || m_graphsOff) {
            gpu::launchBuildCellList(a, stream);
            return;
        }
        if (!(m_exec && sameBuild(a, m_built) && stream == m_builtOn)) {
            forgetGraph();
            cudaGraph_t captured = nullptr;
            bool made = cudaStreamBeginCapture(stream, cudaStreamCaptureModeRelaxed) == cudaSuccess;
            if (made) {
                try {
                    gpu::launchBuildCellList(a, stream);
                } catch (const std::exception&) {
                    made = false;
                }
                made = cudaStreamEndCapture(stream, &captured) == cudaSuccess && made;
            }
            made = made && cudaGraphInstantiate(&m_exec, captured, 0) == cudaSuccess;
            if (captured) cudaGraphDestroy(captured);
            if (!made) {  // nothing was launched: plain launches from now on
                cudaGetLastError();
                forgetGraph();
                m_graphsOff = true;
                gpu::launchBuildCellList(a, stream);
                return;
            }
            m_built = a;
            m_builtOn = stream;
        }
        const cudaError_t e = cudaGraphLaunch(m_exec, stream);
        if (e != cudaSuccess) throw DeviceError(std::string("cell list graph launch: ") + cudaGetErrorString(e));
    }

    static bool sameBuild(const gpu::CellListArgs<Real>& a, const gpu::CellListArgs<Real>& b) {
        for (int k = 0; k < 3; ++k)
            if (a.geometry.dims[k] != b.geometry.dims[k] || a.geometry.inverseCell[k] != b.geometry.inverseCell[k]) return false;
        return a.x == b.x && a.n == b.n && a.cellStart == b.cellStart && a.sorted == b.sorted && a.keys == b.keys &&
               a.sortedKeys == b.sortedKeys && a.indices == b.indices && a.scratch == b.scratch && a.scratchBytes == b.scratchBytes &&
               a.split.species == b.split.species && a.split.radius == b.split.radius && a.split.largeAbove == b.split.largeAbove;
    }

    void forgetGraph() {
        if (m_exec) cudaGraphExecDestroy(m_exec);  // one still running completes first
        m_exec = nullptr;
    }

    static constexpr int64_t kOneLaunchBuild = 4096;  // cell_list_kernels.cu: kOneBlockItems
    DeviceBuffer<int32_t> m_cellStart, m_sorted, m_indices;
    DeviceBuffer<uint32_t> m_keys, m_sortedKeys;
    DeviceBuffer<unsigned char> m_scratch;
    int64_t m_scratchFor = -1;
    size_t m_scratchBytes = 0;
    cudaGraphExec_t m_exec = nullptr;
    gpu::CellListArgs<Real> m_built{};
    cudaStream_t m_builtOn = nullptr;
    bool m_graphsOff = false;
};

}  // namespace corebox
