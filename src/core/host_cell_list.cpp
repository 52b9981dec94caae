#include "host_cell_list.h"

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <string>

namespace corebox {

CellSplitChoice chooseCellSplit(const std::vector<double>& radius, const std::vector<int64_t>& count) {
    CellSplitChoice choice;
    if (radius.empty()) return choice;
    const double largest = *std::max_element(radius.begin(), radius.end());
    choice.gridRadius = largest;
    std::vector<double> candidates(radius);
    std::sort(candidates.begin(), candidates.end());
    for (const double r : candidates) {
        if (r >= largest) break;
        // A radius within a thousandth above r would sit on either side of the threshold by rounding:
        // not a place to split.
        double next = largest, above = 0;
        bool tooClose = false;
        for (size_t s = 0; s < radius.size(); ++s) {
            if (!(radius[s] > r)) continue;
            if (radius[s] <= r * 1.001 + 1e-12) tooClose = true;
            next = std::min(next, radius[s]);
            above += double(s < count.size() ? count[s] : 0);
        }
        if (tooClose || above > double(kMaxLargeParticles)) continue;
        if (largest >= kLargeRatio * r) {
            choice.gridRadius = r;
            choice.largeAbove = 0.5 * (r + next);
        }
        break;
    }
    return choice;
}

std::vector<int64_t> speciesCounts(const std::vector<int32_t>& species, int speciesCount) {
    std::vector<int64_t> counts(size_t(std::max(speciesCount, 0)), 0);
    for (const int32_t s : species) {
        if (s >= 0 && s < speciesCount) ++counts[size_t(s)];
    }
    return counts;
}

template <class Real>
void CellList::build(const Vec3<Real>* x, int64_t n, const CellGeometry& geometry, const CellSplit<Real>& split, double gridRadius) {
    if (n < 0 || n > int64_t(std::numeric_limits<int32_t>::max())) {
        throw std::length_error("cell list: " + std::to_string(n) + " particles, at most " +
                                std::to_string(std::numeric_limits<int32_t>::max()) + " fit its int32 indices");
    }
    m_geometry = geometry;
    const size_t cells = size_t(geometry.cellCount());
    // Keys 0 .. cells (cells: kept out of the cells), counted into cellStart[key + 1] so that the running
    // sum leaves each key's first slot at cellStart[key]; the entry past cells is dropped at the end.
    m_cellStart.assign(cells + 2, 0);
    m_cellOf.resize(size_t(n));
    for (int64_t i = 0; i < n; ++i) {
        const int32_t key = int32_t(cellKeyOfParticle(geometry, split, i, x[i]));
        m_cellOf[size_t(i)] = key;
        ++m_cellStart[size_t(key) + 1];
    }
    for (size_t c = 0; c <= cells; ++c) m_cellStart[c + 1] += m_cellStart[c];
    // Scatter in ascending i: ascending indices inside every cell. cellStart is advanced as the fill
    // pointer and shifted back afterwards, which saves a copy.
    m_sorted.resize(size_t(n));
    for (int64_t i = 0; i < n; ++i) m_sorted[size_t(m_cellStart[size_t(m_cellOf[size_t(i)])]++)] = int32_t(i);
    for (size_t c = cells + 1; c > 0; --c) m_cellStart[c] = m_cellStart[c - 1];
    m_cellStart[0] = 0;
    m_cellStart.resize(cells + 1);
    const CellListView made = splitView(view(), largeAboveOf(split), gridRadius, n);
    m_largeAbove = made.largeAbove;
    m_largeReach = made.largeReach;
}

template void CellList::build<float>(const Vec3<float>*, int64_t, const CellGeometry&, const CellSplit<float>&, double);
template void CellList::build<double>(const Vec3<double>*, int64_t, const CellGeometry&, const CellSplit<double>&, double);

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
