// The cell list on a device (kernels/cell_list.h, built by kernels/cell_list_kernels.cu): owns the
// sort's buffers and rebuilds them from positions on a stream. The view it returns is what the
// contact search (and later the neighbour lists of cut-off forces) walk.
#pragma once

#include <cuda_runtime_api.h>

#include <array>
#include <cstdint>
#include <string>
#include <utility>

#include "cuda_check.h"
#include "device_buffer.h"
#include "gpu_launch.h"
#include "graph_capture.h"

namespace corebox {

template <class Real>
class DeviceCellList {
public:
    DeviceCellList() = default;
    DeviceCellList(const DeviceCellList&) = delete;
    DeviceCellList& operator=(const DeviceCellList&) = delete;
    ~DeviceCellList() { forgetGraphs(); }

    // Enqueues the build of n positions x (device memory) with `geometry` on `stream`; the view's
    // arrays are valid once the stream reaches this point, until the next build.
    CellListView build(const Vec3<Real>* x, int64_t n, const CellGeometry& geometry, cudaStream_t stream) {
        return build(x, n, geometry, CellSplit<Real>{}, 0.0, stream);
    }
    // The same, keeping the particles `split` names (device pointers) out of the cells; gridRadius: the
    // largest radius left in them (chooseCellSplit).
    CellListView build(const Vec3<Real>* x, int64_t n, const CellGeometry& geometry, const CellSplit<Real>& split, double gridRadius,
                       cudaStream_t stream) {
        const gpu::CellListArgs<Real> a = argsFor(x, n, geometry, split, gridRadius);
        launch(a, stream);
        return a.view();
    }
    // The same build, skipped on the device where *moved is 0 when the stream reaches it, and *moved
    // cleared. The caller's promise: since the last build into this list, positions changed only where
    // a kernel set *moved on seeing a particle leave the cell keys() gives it. A skipped build leaves the
    // arrays a build would make: they depend on the keys alone (ascending key, then index). Where the
    // last build had other arguments, or wrote no keys (keys() null), or conditional graphs are refused,
    // a plain build.
    CellListView rebuildIfMoved(const Vec3<Real>* x, int64_t n, const CellGeometry& geometry,
                                const CellSplit<Real>& split, double gridRadius, unsigned int* moved,
                                cudaStream_t stream) {
        const gpu::CellListArgs<Real> a = argsFor(x, n, geometry, split, gridRadius);
        if (!(m_keysValid && sameBuild(a, m_last)) || stream == nullptr || m_gatedOff) {
            launch(a, stream);
            return a.view();
        }
        Graph* graph = nullptr;
        for (Graph& g : m_gated)
            if (g.exec && g.stream == stream && g.moved == moved && sameBuild(a, g.args)) graph = &g;
        if (!graph) {
            graph = leastRecentlyUsed(m_gated);
            forget(*graph);
            graph->exec = captureConditionalGraph(
                stream, [&](cudaGraphConditionalHandle handle) { gpu::launchCellListGate(handle, moved, stream); },
                [&] { gpu::launchBuildCellList(a, stream); });
            if (!graph->exec) {  // refused: plain builds from now on
                m_gatedOff = true;
                launch(a, stream);
                return a.view();
            }
            graph->args = a;
            graph->stream = stream;
            graph->moved = moved;
        }
        run(*graph, stream);
        return a.view();
    }
    // Each particle's cell key at the last build (device memory, n), where that build wrote them (the
    // radix-sort builds, above cellListBuildIsOneLaunch); null otherwise.
    const uint32_t* keys() const { return m_keysValid ? m_keys.data() : nullptr; }

private:
    gpu::CellListArgs<Real> argsFor(const Vec3<Real>* x, int64_t n, const CellGeometry& geometry,
                                    const CellSplit<Real>& split, double gridRadius) {
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
        return a;
    }

public:

    // Buffers and the captured builds travel together (the graphs' arguments are these buffers).
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
        swap(a.m_graphs, b.m_graphs);
        swap(a.m_graphsOff, b.m_graphsOff);
        swap(a.m_gated, b.m_gated);
        swap(a.m_gatedOff, b.m_gatedOff);
        swap(a.m_last, b.m_last);
        swap(a.m_keysValid, b.m_keysValid);
    }

private:
    // A build of more than one launch (keys, the radix sort's passes, the cell starts) costs the host
    // about 35 us, CUB's side most of it (an H200's host, 10^5 particles: 37 of a collision round's 44
    // us of enqueueing), and a collision round builds one. So each build is captured into a graph the
    // first time its arguments are seen and the graph launched while they are the same: a change of
    // positions' buffer, count, geometry or split is another graph. A few are kept (the impact search's
    // grid and the contact listing's, a little wider, alternate within a step), the least recently
    // used replaced. Not on the legacy default stream (no capture there) nor for builds of one launch.
    // The builds rebuildIfMoved gates (a conditional graph each, the same arguments and the flag) are kept
    // apart from these.
    struct Graph {
        gpu::CellListArgs<Real> args{};
        cudaStream_t stream = nullptr;
        cudaGraphExec_t exec = nullptr;
        unsigned int* moved = nullptr;  // the gate's flag
        uint64_t used = 0;  // when last launched (m_launches)
    };
    static constexpr size_t kGraphs = 4;

    static Graph* leastRecentlyUsed(std::array<Graph, kGraphs>& graphs) {
        Graph* oldest = &graphs[0];
        for (Graph& g : graphs)
            if (g.used < oldest->used) oldest = &g;  // or an empty one
        return oldest;
    }

    void run(Graph& graph, cudaStream_t stream) {
        graph.used = ++m_launches;
        const cudaError_t e = cudaGraphLaunch(graph.exec, stream);
        if (e != cudaSuccess) throw DeviceError(std::string("cell list graph launch: ") + cudaGetErrorString(e));
    }

    void launch(const gpu::CellListArgs<Real>& a, cudaStream_t stream) {
        m_last = a;
        m_keysValid = !gpu::cellListBuildIsOneLaunch(a.n);  // the one-launch builds write no keys
        if (stream == nullptr || gpu::cellListBuildIsOneLaunch(a.n) || m_graphsOff) {
            gpu::launchBuildCellList(a, stream);
            return;
        }
        Graph* graph = nullptr;
        for (Graph& g : m_graphs)
            if (g.exec && g.stream == stream && sameBuild(a, g.args)) graph = &g;
        if (!graph) {
            graph = leastRecentlyUsed(m_graphs);
            forget(*graph);
            graph->exec = captureGraph(stream, [&] { gpu::launchBuildCellList(a, stream); });
            if (!graph->exec) {  // nothing was launched: plain launches from now on
                m_graphsOff = true;
                gpu::launchBuildCellList(a, stream);
                return;
            }
            graph->args = a;
            graph->stream = stream;
        }
        run(*graph, stream);
    }

    static bool sameBuild(const gpu::CellListArgs<Real>& a, const gpu::CellListArgs<Real>& b) {
        return sameGeometry(a.geometry, b.geometry) && a.x == b.x && a.n == b.n && a.cellStart == b.cellStart &&
               a.sorted == b.sorted && a.keys == b.keys && a.sortedKeys == b.sortedKeys && a.indices == b.indices &&
               a.scratch == b.scratch && a.scratchBytes == b.scratchBytes && a.split.species == b.split.species &&
               a.split.radius == b.split.radius && a.split.largeAbove == b.split.largeAbove;
    }

    static void forget(Graph& g) {
        if (g.exec) cudaGraphExecDestroy(g.exec);  // one still running completes first
        g = Graph{};
    }
    void forgetGraphs() {
        for (Graph& g : m_graphs) forget(g);
        for (Graph& g : m_gated) forget(g);
    }

    DeviceBuffer<int32_t> m_cellStart, m_sorted, m_indices;
    DeviceBuffer<uint32_t> m_keys, m_sortedKeys;
    DeviceBuffer<unsigned char> m_scratch;
    int64_t m_scratchFor = -1;
    size_t m_scratchBytes = 0;
    std::array<Graph, kGraphs> m_graphs{}, m_gated{};
    uint64_t m_launches = 0;
    bool m_graphsOff = false, m_gatedOff = false;
    gpu::CellListArgs<Real> m_last{};  // the last build's arguments (launch)
    bool m_keysValid = false;          // m_keys holds the last build's keys
};

}  // namespace corebox
