// The cell list on a device (kernels/cell_list.h, built by kernels/cell_list_kernels.cu): owns the
// sort's buffers and rebuilds them from positions on a stream. The view it returns is what the
// contact search (and later the neighbour lists of cut-off forces) walk.
#pragma once

#include <cuda_runtime_api.h>

#include <algorithm>
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
    // cleared there. The caller's promise: since the last build into this list, positions changed only
    // where a kernel set *moved on seeing a particle leave the cell keys() gives it. A skipped build
    // leaves the arrays a build would make: they depend on the keys alone (ascending key, then index).
    // The gate and the build are one cooperative launch (gpu::launchCellListIfMoved), whose skip costs
    // a launch. Where the last build had other arguments, or wrote no keys (keys() null), or the device
    // has no cooperative launch, a plain build, which leaves *moved as it was (a stale 1 costs one build
    // more, never a wrong list).
    // Before, the gate was a graph's IF node around the counted build: an H200, fp32, CUPTI (the 10^6-ball
    // pile, 5 s, 24,347 gated rounds, 15,302 of them building) saw the GPU wait 22 us between the gate and
    // the body's first node of each build, 6 to 7 us at each graph's entry and at the crowded build's
    // nested IF: 560 ms of the 1.24 s the GPU stood idle. One launch: the same arrays and bits (the pile's
    // energies, the sandbox example's state hash); the GPU idle 0.70 s; `corebox bench pile` (separate
    // runs alternating in one call) 10^6 balls 36.11 ms a frame against 37.74 and 38.43, 10^5 9.00 against
    // 10.27, 10^4 5.00 against 5.52; the sandbox example at 10^5 balls 12.6 against 12.6 and 12.7.
    // Tried and not kept (an H200, fp32, the 10^6-ball pile, CUPTI kernel times over its 5 s): the
    // counts zeroed by the build that read them (its scan), so that the next gated build could skip its
    // zeroing pass and that pass's barrier: the gated builds took 40.4 us on average against 36.3 (the
    // count's atomics then found the counts' lines out of L2); the counted builds of launch() as this
    // cooperative launch too (no graph, no IF node): 1,213 ms of builds against 1,145, the pile 34.6 ms a
    // frame against 33.9 (separate binaries in one call).
    CellListView rebuildIfMoved(const Vec3<Real>* x, int64_t n, const CellGeometry& geometry,
                                const CellSplit<Real>& split, double gridRadius, unsigned int* moved,
                                cudaStream_t stream) {
        gpu::CellListArgs<Real> a{};
        int32_t* blockTotals = nullptr;
        if (gatedBuild(x, n, geometry, split, gridRadius, gpu::cellListIfMovedBlocks<Real>(), stream, &a, &blockTotals))
            gpu::launchCellListIfMoved(a, moved, blockTotals, stream);
        return a.view();
    }
    // rebuildIfMoved's choice, for a caller whose own cooperative launch makes the gated build and then
    // work of its own (gpu::launchCellListIfMovedThenFill): where the build can gate itself, its arguments
    // and the block totals' scratch for `blocks` blocks, and true; else the plain build made, its arguments,
    // and false.
    bool gatedBuild(const Vec3<Real>* x, int64_t n, const CellGeometry& geometry, const CellSplit<Real>& split,
                    double gridRadius, int blocks, cudaStream_t stream, gpu::CellListArgs<Real>* args,
                    int32_t** blockTotals) {
        *args = argsFor(x, n, geometry, split, gridRadius);
        if (!(m_keysValid && sameBuild(*args, m_last)) || !gatesOnDevice(*args)) {
            launch(*args, stream);
            return false;
        }
        m_blockTotals.resize(size_t(std::max(blocks, 1)));
        *blockTotals = m_blockTotals.data();
        return true;
    }
    // Each particle's cell key at the last build (device memory, n), where that build wrote them (the
    // builds above cellListBuildIsOneLaunch); null otherwise.
    const uint32_t* keys() const { return m_keysValid ? m_keys.data() : nullptr; }
    // Whether builds in graphs sort by counting (gpu::launchCountedCellList): false once the driver
    // refused a conditional node, or graphs altogether (for the tests).
    bool buildsByCounting() const { return !m_countedOff && !m_graphsOff; }

private:
    // Whether rebuildIfMoved's build can gate itself (gpu::launchCellListIfMoved): a counted build of
    // several blocks on a device with cooperative launches, of a grid within the counted builds' bound
    // (enqueueBuild sorts a larger one by radix), so that both kinds of build see the same grids.
    static bool gatesOnDevice(const gpu::CellListArgs<Real>& a) {
        return !gpu::cellListBuildIsOneLaunch(a.n) && int64_t(a.geometry.cellCount()) <= maxCellCount(a.n) &&
               gpu::cellListIfMovedBlocks<Real>() > 0;
    }

    gpu::CellListArgs<Real> argsFor(const Vec3<Real>* x, int64_t n, const CellGeometry& geometry,
                                    const CellSplit<Real>& split, double gridRadius) {
        m_keys.resize(size_t(n));
        m_sortedKeys.resize(size_t(n));
        m_indices.resize(size_t(n));
        m_sorted.resize(size_t(n));
        m_cellStart.resize(size_t(geometry.cellCount()) + 1);
        m_counts.resize(size_t(geometry.cellCount()) + 1);
        m_crowded.resize(1);
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
        a.counts = m_counts.data();
        a.crowded = m_crowded.data();
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
        swap(a.m_last, b.m_last);
        swap(a.m_keysValid, b.m_keysValid);
        swap(a.m_counts, b.m_counts);
        swap(a.m_blockTotals, b.m_blockTotals);
        swap(a.m_crowded, b.m_crowded);
        swap(a.m_countedOff, b.m_countedOff);
        swap(a.m_helper, b.m_helper);
    }

private:
    // A build of more than one launch (keys, the radix sort's passes, the cell starts) costs the host
    // about 35 us, CUB's side most of it (an H200's host, 10^5 particles: 37 of a collision round's 44
    // us of enqueueing), and a collision round builds one. So each build is captured into a graph the
    // first time its arguments are seen and the graph launched while they are the same: a change of
    // positions' buffer, count, geometry or split is another graph. A few are kept (the impact search's
    // grid and the contact listing's, a little wider, alternate within a step), the least recently
    // used replaced. Not on the legacy default stream (no capture there) nor for builds of one launch.
    struct Graph {
        gpu::CellListArgs<Real> args{};
        cudaStream_t stream = nullptr;
        cudaGraphExec_t exec = nullptr;
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
            makeHelper();
            graph->exec = captureGraph(stream, [&] { enqueueBuild(a, stream); });
            if (!graph->exec && !m_countedOff) {  // no conditional nodes: the radix builds alone
                m_countedOff = true;
                graph->exec = captureGraph(stream, [&] { enqueueBuild(a, stream); });
            }
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

    // A build as a graph captures it: the counting sort with the radix build as its fallback where a cell
    // is crowded (gpu::launchCountedCellList, the IF node's body captured on the helper stream); the
    // radix build alone where conditional nodes were refused.
    // Why counting: a radix build is a keys pass, CUB's histogram and three passes over (key, index) of
    // every particle, and a binary search a cell; the counting build one pass of atomics, a scan of the
    // counts, a placing pass and a short insertion sort a cell. The same arrays; an H200 (fp32, the same
    // call, twice each): the sandbox example at 10^5 balls 13.3 and 12.9 ms a frame against 13.6 and
    // 14.5, its impact rounds 3.4 and 3.7 against 4.2 and 4.1, the slowest frame 50 and 49 against 55 and
    // 56; `corebox bench pile` 10^5 balls 11.2 and 10.8 against 11.7 and 11.9, 10^6 47.2 and 47.0 against
    // 47.4 and 47.5, 10^4 within noise (5.8, 5.6 against 5.5, 5.7).
    void enqueueBuild(const gpu::CellListArgs<Real>& a, cudaStream_t stream) {
        // The scan's scratch holds maxCellCount(n) + 1 counts (gpu::cellListScratchBytes), which every
        // geometry of cellGeometry respects; one made otherwise sorts by radix.
        if (m_countedOff || int64_t(a.geometry.cellCount()) > maxCellCount(a.n)) {
            gpu::launchBuildCellList(a, stream);
            return;
        }
        enqueueIf(
            stream, m_helper,
            [&](cudaGraphConditionalHandle crowded) { gpu::launchCountedCellList(a, crowded, stream); },
            [&](cudaStream_t body) { gpu::launchBuildCellList(a, body); });
    }

    // The idle stream that captures the body of the IF node, made on the current device (the stream's:
    // the caller's) before a capture begins, since a capturing stream's device cannot be asked.
    void makeHelper() {
        if (!m_helper && cudaStreamCreateWithFlags(&m_helper, cudaStreamNonBlocking) != cudaSuccess) {
            m_helper = nullptr;
            throw DeviceError("cell list helper stream: create");
        }
    }

    static bool sameBuild(const gpu::CellListArgs<Real>& a, const gpu::CellListArgs<Real>& b) {
        return sameGeometry(a.geometry, b.geometry) && a.x == b.x && a.n == b.n && a.cellStart == b.cellStart &&
               a.sorted == b.sorted && a.keys == b.keys && a.sortedKeys == b.sortedKeys && a.indices == b.indices &&
               a.scratch == b.scratch && a.scratchBytes == b.scratchBytes && a.split.species == b.split.species &&
               a.split.radius == b.split.radius && a.split.largeAbove == b.split.largeAbove && a.counts == b.counts &&
               a.crowded == b.crowded;
    }

    static void forget(Graph& g) {
        if (g.exec) cudaGraphExecDestroy(g.exec);  // one still running completes first
        g = Graph{};
    }
    void forgetGraphs() {
        for (Graph& g : m_graphs) forget(g);
        if (m_helper) cudaStreamDestroy(m_helper);
        m_helper = nullptr;
    }

    DeviceBuffer<int32_t> m_cellStart, m_sorted, m_indices;
    DeviceBuffer<uint32_t> m_keys, m_sortedKeys;
    DeviceBuffer<unsigned char> m_scratch;
    int64_t m_scratchFor = -1;
    size_t m_scratchBytes = 0;
    std::array<Graph, kGraphs> m_graphs{};
    uint64_t m_launches = 0;
    bool m_graphsOff = false;
    DeviceBuffer<int32_t> m_counts, m_blockTotals;
    DeviceBuffer<unsigned int> m_crowded;
    bool m_countedOff = false;                // conditional nodes refused: radix builds in the graphs
    cudaStream_t m_helper = nullptr;          // enqueueIf's helper
    gpu::CellListArgs<Real> m_last{};  // the last build's arguments (launch)
    bool m_keysValid = false;          // m_keys holds the last build's keys
};

}  // namespace corebox
