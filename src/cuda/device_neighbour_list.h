// One GPU's neighbour lists (kernels/neighbour_list_kernels.cu): for its rows [begin, end) over all n
// positions, so that with several GPUs each builds the lists of its own slice from the gathered
// positions. Lists of every particle run their rows in the cell list's order (launchListRowOrder).
// Rebuilt when some row has moved more than skin / 2 since the build (a flag read back once per force
// pass, unless the caller already knows: the one-wait step's forecast, src/cuda/cuda_step.cpp), when
// the reach, the rows or the box changed, and again with more columns when a row had more partners
// than the lists held.
#pragma once

#include <cuda_runtime_api.h>

#include <algorithm>

#include "cuda_check.h"
#include "device_buffer.h"
#include "device_cell_list.h"
#include "gpu_launch.h"
#include "pinned_buffer.h"

namespace corebox {

template <class Real>
class DeviceNeighbourList {
public:
    // What the caller knows of the rows' displacement since the build at x: nothing (the lists check,
    // waiting for the stream once), that no row moved past half the skin, or that one did.
    enum class Displacement { Unknown, WithinHalfSkin, BeyondHalfSkin };
    // Makes the lists valid for x (all n positions, device memory of the current GPU) on `stream`.
    // Returns true when it rebuilt them.
    bool update(const Vec3<Real>* x, int64_t n, int64_t begin, int64_t end, const Vec3<Real>& box, double cutoff, double skin,
                cudaStream_t stream, Displacement known = Displacement::Unknown) {
        const bool same = m_valid && n == m_n && begin == m_begin && end == m_end && cutoff == m_cutoff && skin == m_skin &&
                          box.x == m_box.x && box.y == m_box.y && box.z == m_box.z;
        if (same && known == Displacement::WithinHalfSkin) return false;
        if (same && known == Displacement::Unknown) {
            gpu::launchListMoved(x, m_xBuilt.data(), begin, end, Real(0.25 * skin * skin), m_flag.data(), stream);
            if (readFlag(stream) == 0) return false;
        }
        m_n = n;
        m_begin = begin;
        m_end = end;
        m_cutoff = cutoff;
        m_skin = skin;
        m_box = box;
        build(x, stream);
        m_valid = true;
        ++m_builds;
        return true;
    }
    void invalidate() { m_valid = false; }
    // Each row's position at the last build (rows of every particle: indexed by particle), or null.
    const Vec3<Real>* builtPositions() const { return m_valid ? m_xBuilt.data() : nullptr; }
    int64_t builds() const { return m_builds; }

    // The list fields of a force pass over the same rows.
    void fill(gpu::ForceArgs<Real>& f) const {
        f.neighbours = m_neighbours.data();
        f.neighbourCount = m_count.data();
        f.listRows = m_end - m_begin;
        f.rowParticle = m_rowParticle.data();
        f.rowOf = m_rowOf.data();
        f.laneStart = m_lanes > 1 ? m_laneStart.data() : nullptr;
    }
    // Marks the rows whose sums read a particle that moved since xBefore (the lists' own rows, which
    // must be every particle: one GPU), for a force pass over those rows only (ForceArgs::rowMask).
    const unsigned char* touchMoved(const Vec3<Real>* x, const Vec3<Real>* xBefore, cudaStream_t stream) {
        return touch(x, xBefore, nullptr, stream);
    }
    // The same for the particles p with moved[p] != 0.
    // The same for the particles p with moved[p] != 0; nothing marked where the gate is closed. With
    // touchedCleared, the caller already zeroed touchedRows() on the stream.
    const unsigned char* touchFlagged(const char* moved, cudaStream_t stream, gpu::StageGate gate = {}, bool touchedCleared = false) {
        return touch(nullptr, nullptr, moved, stream, gate, touchedCleared);
    }
    // The row mask the touch calls fill, a byte per row.
    unsigned char* touchedRows() {
        m_touched.resize(size_t(std::max<int64_t>(m_end - m_begin, 1)));
        return m_touched.data();
    }

private:
    const unsigned char* touch(const Vec3<Real>* x, const Vec3<Real>* xBefore, const char* moved, cudaStream_t stream,
                               gpu::StageGate gate = {}, bool touchedCleared = false) {
        gpu::launchTouchMoved(x, xBefore, moved, m_end - m_begin, m_rowOf.data(), m_neighbours.data(), m_count.data(), touchedRows(), stream,
                              gate, touchedCleared);
        return m_touched.data();
    }

    unsigned int readFlag(cudaStream_t stream) {
        unsigned int* host = m_hostFlag.resize(1);
        cudaCheck(cudaMemcpyAsync(host, m_flag.data(), sizeof(unsigned int), cudaMemcpyDeviceToHost, stream), "list flag read-back");
        cudaCheck(cudaStreamSynchronize(stream), "list flag read-back");
        return *host;
    }

    void build(const Vec3<Real>* x, cudaStream_t stream) {
        const int64_t rows = m_end - m_begin;
        const double reach = m_cutoff + m_skin;
        const CellListView cells = m_cells.build(x, m_n, cellGeometry(vec3Cast<double>(m_box), m_n, reach), stream);
        m_cellEntries.resize(size_t(std::max<int64_t>(m_n, 1)));
        gpu::launchGatherCellEntries(x, cells.sorted, m_n, m_cellEntries.data(), stream);
        m_count.resize(size_t(std::max<int64_t>(rows, 1)));
        m_rowParticle.resize(size_t(std::max<int64_t>(rows, 1)));
        m_rowOf.resize(size_t(std::max<int64_t>(rows, 1)));
        gpu::launchListRowOrder(cells, m_n, m_begin, m_end, m_rowParticle.data(), m_rowOf.data(), stream);
        m_flag.resize(1);
        m_lanes = gpu::listLanes(m_n);
        m_laneStart.resize(size_t(std::max<int64_t>(rows, 1)) * size_t(m_lanes));
        for (;;) {
            m_neighbours.resize(size_t(std::max<int64_t>(rows, 1)) * size_t(m_columns));
            gpu::NeighbourListArgs<Real> a{x,
                                           m_n,
                                           m_begin,
                                           m_end,
                                           m_rowParticle.data(),
                                           cells,
                                           m_cellEntries.data(),
                                           Real(reach * reach),
                                           m_columns,
                                           m_neighbours.data(),
                                           m_count.data(),
                                           m_flag.data(),
                                           m_lanes,
                                           m_laneStart.data()};
            gpu::launchBuildNeighbourList(a, stream);
            const unsigned int most = readFlag(stream);
            if (most <= unsigned(m_columns)) break;
            m_columns = int32_t(most + most / 4 + 8);  // room for the density to fluctuate before the next growth
        }
        m_xBuilt.resize(size_t(std::max<int64_t>(rows, 1)));
        if (rows > 0)
            cudaCheck(cudaMemcpyAsync(m_xBuilt.data(), x + m_begin, size_t(rows) * sizeof(Vec3<Real>), cudaMemcpyDeviceToDevice, stream),
                      "list positions copy");
    }

    DeviceCellList<Real> m_cells;
    DeviceBuffer<gpu::CellEntry<Real>> m_cellEntries;  // the cell list's particles with their positions, in its order
    DeviceBuffer<int32_t> m_neighbours, m_count;
    DeviceBuffer<int32_t> m_rowParticle, m_rowOf;  // rows in cell order (one GPU), and back
    DeviceBuffer<int32_t> m_laneStart;             // NeighbourListArgs::laneStart
    int m_lanes = 1;
    DeviceBuffer<Vec3<Real>> m_xBuilt;
    DeviceBuffer<unsigned int> m_flag;  // the displacement flag, then the build's largest count
    DeviceBuffer<unsigned char> m_touched;  // touchMoved's row mask
    PinnedBuffer<unsigned int> m_hostFlag;
    int32_t m_columns = 96;  // LJ liquid at r_c + skin = 2.8 has ~75 partners
    int64_t m_n = 0, m_begin = 0, m_end = 0;
    double m_cutoff = 0, m_skin = 0;
    Vec3<Real> m_box{0, 0, 0};
    bool m_valid = false;
    int64_t m_builds = 0;
};

}  // namespace corebox
