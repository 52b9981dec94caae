// One GPU's neighbour lists (kernels/neighbour_list_kernels.cu): for its rows [begin, end) over all n
// positions, so that with several GPUs each builds the lists of its own slice from the gathered
// positions. Lists of every particle run their rows in the cell list's order (launchListRowOrder).
// Rebuilt when some row has moved more than skin / 2 since the build (a flag read back once per force
// pass, unless the caller already knows: the one-wait step's forecast, src/cuda/cuda_step.cpp), when
// the reach, the rows or the box changed, and again with more columns when a row had more partners
// than the lists held. A build may also be left unchecked (update's `overflow`): launched with the
// columns it has, its overflow flagged on the device for gated launches and checked later (checked,
// settle), so that a step that runs ahead can build its own lists with no wait (src/cuda/cuda_step.cpp).
#pragma once

#include <cuda_runtime_api.h>

#include <algorithm>
#include <atomic>
#include <stdexcept>
#include <utility>

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
    // With `overflow` (a device word, zero before) a build is not waited for: it uses the columns the
    // lists have and sets *overflow to 1 where a row has more partners (the lists are then unusable
    // until settled: launches after it gate on the word).
    bool update(const Vec3<Real>* x, int64_t n, int64_t begin, int64_t end, const Vec3<Real>& box, double cutoff, double skin,
                cudaStream_t stream, Displacement known = Displacement::Unknown, unsigned int* overflow = nullptr) {
        if (m_unchecked) settle(stream);
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
        build(x, stream, overflow);
        m_valid = true;
        ++m_builds;
        m_buildId = ++s_buildIds;
        return true;
    }
    void invalidate() {
        m_valid = false;
        m_unchecked = false;
    }
    // An unchecked build's verdict, read by the caller from its overflow word: none, or the lists are
    // built again with more columns (waiting for the stream).
    void checked(bool overflowed, cudaStream_t stream) {
        if (!m_unchecked) return;
        if (overflowed) settle(stream);
        m_unchecked = false;
    }
    // Checks an unchecked build by waiting for it, and builds again with more columns where it overflowed.
    void settle(cudaStream_t stream) {
        if (!m_unchecked) return;
        m_unchecked = false;
        const unsigned int most = readFlag(stream);
        if (most <= unsigned(m_columns)) return;
        m_columns = grownColumns(most);
        build(m_uncheckedX, stream);
    }
    int32_t columns() const { return m_columns; }
    void setColumns(int32_t columns) { m_columns = columns; }
    // Distinct for every build of every list (a swap brings its lists' id along).
    int64_t buildId() const { return m_buildId; }
    // Exchanges the built lists (everything but the read-back buffer) with `other`.
    void swap(DeviceNeighbourList& other) {
        using std::swap;
        swap(m_cells, other.m_cells);
        swap(m_cellEntries, other.m_cellEntries);
        swap(m_neighbours, other.m_neighbours);
        swap(m_count, other.m_count);
        swap(m_rowParticle, other.m_rowParticle);
        swap(m_rowOf, other.m_rowOf);
        swap(m_laneStart, other.m_laneStart);
        swap(m_lanes, other.m_lanes);
        swap(m_xBuilt, other.m_xBuilt);
        swap(m_flag, other.m_flag);
        swap(m_touched, other.m_touched);
        swap(m_columns, other.m_columns);
        swap(m_n, other.m_n);
        swap(m_begin, other.m_begin);
        swap(m_end, other.m_end);
        swap(m_cutoff, other.m_cutoff);
        swap(m_skin, other.m_skin);
        swap(m_box, other.m_box);
        swap(m_valid, other.m_valid);
        swap(m_builds, other.m_builds);
        swap(m_buildId, other.m_buildId);
        swap(m_unchecked, other.m_unchecked);
        swap(m_uncheckedX, other.m_uncheckedX);
    }
    // Each row's position at the last build (rows of every particle: indexed by particle), or null.
    const Vec3<Real>* builtPositions() const { return m_valid ? m_xBuilt.data() : nullptr; }
    int64_t builds() const { return m_builds; }

    // The list fields of a force pass over the same rows (fillUnchecked: also after an unchecked build,
    // for a launch gated on its overflow word).
    void fill(gpu::ForceArgs<Real>& f) const {
        if (m_unchecked) throw std::logic_error("neighbour list: used before its unchecked build was checked");
        fillUnchecked(f);
    }
    void fillUnchecked(gpu::ForceArgs<Real>& f) const {
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
    const unsigned char* touchFlagged(const char* moved, cudaStream_t stream) { return touch(nullptr, nullptr, moved, stream); }

private:
    // The row mask the touch calls fill, a byte per row.
    unsigned char* touchedRows() {
        m_touched.resize(size_t(std::max<int64_t>(m_end - m_begin, 1)));
        return m_touched.data();
    }

    const unsigned char* touch(const Vec3<Real>* x, const Vec3<Real>* xBefore, const char* moved, cudaStream_t stream) {
        gpu::launchTouchMoved(x, xBefore, moved, m_end - m_begin, m_rowOf.data(), m_neighbours.data(), m_count.data(), touchedRows(), stream);
        return m_touched.data();
    }

    unsigned int readFlag(cudaStream_t stream) {
        unsigned int* host = m_hostFlag.resize(1);
        cudaCheck(cudaMemcpyAsync(host, m_flag.data(), sizeof(unsigned int), cudaMemcpyDeviceToHost, stream), "list flag read-back");
        cudaCheck(cudaStreamSynchronize(stream), "list flag read-back");
        return *host;
    }

    static int32_t grownColumns(unsigned int most) { return int32_t(most + most / 4 + 8); }  // room for the density to fluctuate

    void build(const Vec3<Real>* x, cudaStream_t stream, unsigned int* overflow = nullptr) {
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
                                           m_laneStart.data(),
                                           overflow};
            gpu::launchBuildNeighbourList(a, stream);
            if (overflow) {
                m_unchecked = true;
                m_uncheckedX = x;
                break;
            }
            const unsigned int most = readFlag(stream);
            if (most <= unsigned(m_columns)) break;
            m_columns = grownColumns(most);
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
    int64_t m_buildId = 0;
    bool m_unchecked = false;                   // the last build's overflow not yet known
    const Vec3<Real>* m_uncheckedX = nullptr;   // its positions, for settle
    static inline std::atomic<int64_t> s_buildIds{0};
};

}  // namespace corebox
