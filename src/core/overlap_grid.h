// Uniform grid over the box for finding hard-core overlaps in O(N) when placing or validating
// particles. Cells are at least the largest contact distance wide, so any overlapping pair lies in
// neighbouring cells.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "vec3.h"

namespace corebox {

class OverlapGrid {
public:
    OverlapGrid(const std::array<double, 3>& box, double cellSize);

    void insert(int64_t id, const Vec3<double>& position);
    // Calls fn(id) for every inserted particle in the 27 cells around `position`.
    template <class Fn>
    void forNeighbours(const Vec3<double>& position, Fn&& fn) const {
        const std::array<int, 3> c = cellOf(position);
        for (int dz = -1; dz <= 1; ++dz)
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const int x = c[0] + dx, y = c[1] + dy, z = c[2] + dz;
                    if (x < 0 || y < 0 || z < 0 || x >= m_dims[0] || y >= m_dims[1] || z >= m_dims[2]) continue;
                    for (int64_t id : m_cells[size_t((z * m_dims[1] + y) * m_dims[0] + x)]) fn(id);
                }
    }

private:
    std::array<int, 3> cellOf(const Vec3<double>& p) const;

    std::array<int, 3> m_dims{};
    std::array<double, 3> m_cellSize{};
    std::vector<std::vector<int64_t>> m_cells;
};

}  // namespace corebox
