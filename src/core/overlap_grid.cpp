#include "overlap_grid.h"

#include <algorithm>
#include <cmath>

namespace corebox {

OverlapGrid::OverlapGrid(const std::array<double, 3>& box, double cellSize) {
    // Cap the cell count so a tiny contact distance in a big box does not allocate a huge grid.
    const double minCell = std::cbrt(box[0] * box[1] * box[2] / 4.0e6);
    const double size = std::max(cellSize, minCell);
    for (int a = 0; a < 3; ++a) {
        m_dims[size_t(a)] = std::max(1, int(box[size_t(a)] / size));
        m_cellSize[size_t(a)] = box[size_t(a)] / m_dims[size_t(a)];
    }
    m_cells.resize(size_t(m_dims[0]) * size_t(m_dims[1]) * size_t(m_dims[2]));
}

std::array<int, 3> OverlapGrid::cellOf(const Vec3<double>& p) const {
    std::array<int, 3> c{};
    for (int a = 0; a < 3; ++a) c[size_t(a)] = std::clamp(int(std::floor(p[a] / m_cellSize[size_t(a)])), 0, m_dims[size_t(a)] - 1);
    return c;
}

void OverlapGrid::insert(int64_t id, const Vec3<double>& position) {
    const std::array<int, 3> c = cellOf(position);
    m_cells[size_t((c[2] * m_dims[1] + c[1]) * m_dims[0] + c[0])].push_back(id);
}

}  // namespace corebox
