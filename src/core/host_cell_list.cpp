#include "host_cell_list.h"

#include <limits>
#include <stdexcept>
#include <string>

namespace corebox {

template <class Real>
void CellList::build(const Vec3<Real>* x, int64_t n, const CellGeometry& geometry) {
    if (n < 0 || n > int64_t(std::numeric_limits<int32_t>::max())) {
        throw std::length_error("cell list: " + std::to_string(n) + " particles, at most " +
                                std::to_string(std::numeric_limits<int32_t>::max()) + " fit its int32 indices");
    }
    m_geometry = geometry;
    const size_t cells = size_t(geometry.cellCount());
    m_cellStart.assign(cells + 1, 0);
    m_cellOf.resize(size_t(n));
    // Count into cellStart[key + 1] so that the running sum leaves each cell's first slot at cellStart[key].
    for (int64_t i = 0; i < n; ++i) {
        const int32_t key = int32_t(cellKeyOf(geometry, x[i]));
        m_cellOf[size_t(i)] = key;
        ++m_cellStart[size_t(key) + 1];
    }
    for (size_t c = 0; c < cells; ++c) m_cellStart[c + 1] += m_cellStart[c];
    // Scatter in ascending i: ascending indices inside every cell. cellStart is advanced as the fill
    // pointer and shifted back afterwards, which saves a copy.
    m_sorted.resize(size_t(n));
    for (int64_t i = 0; i < n; ++i) m_sorted[size_t(m_cellStart[size_t(m_cellOf[size_t(i)])]++)] = int32_t(i);
    for (size_t c = cells; c > 0; --c) m_cellStart[c] = m_cellStart[c - 1];
    m_cellStart[0] = 0;
}

template void CellList::build<float>(const Vec3<float>*, int64_t, const CellGeometry&);
template void CellList::build<double>(const Vec3<double>*, int64_t, const CellGeometry&);

IncrementalCellList::IncrementalCellList(const CellGeometry& geometry, int64_t capacity)
    : m_geometry(geometry),
      m_head(size_t(geometry.cellCount()), -1),
      m_tail(size_t(geometry.cellCount()), -1),
      m_next(size_t(capacity > 0 ? capacity : 0), -1) {}

void IncrementalCellList::insert(int64_t index, const Vec3<double>& position) {
    const size_t cell = size_t(cellKeyOf(m_geometry, position));
    if (m_tail[cell] >= 0) m_next[size_t(m_tail[cell])] = index;
    else m_head[cell] = index;
    m_tail[cell] = index;
}

}  // namespace corebox
