// Uniform grid for hard-core contact search. Contacts are short-ranged (at most the largest
// a_i + a_j), so with cells at least that wide every overlapping pair lies in neighbouring cells and
// a collision round costs O(N) instead of O(N^2). Rebuilt by a counting sort at every round, since
// resolution moves particles. Neighbours are visited in ascending cell order and, within a cell, in
// ascending particle index, so results do not depend on the thread count.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "vec3.h"

namespace corebox {

template <class Real>
class ContactGrid {
public:
    // box: edge lengths; reach: the largest contact distance.
    void build(const std::vector<Vec3<Real>>& x, const Vec3<Real>& box, double reach) {
        const int64_t n = int64_t(x.size());
        // At most ~2 cells per particle and at least one cell per axis.
        const double volume = double(box.x) * double(box.y) * double(box.z);
        const double minCell = std::cbrt(volume / double(std::max<int64_t>(2 * n, 1)));
        const double cell = std::max(reach, minCell);
        for (int a = 0; a < 3; ++a) {
            m_dims[size_t(a)] = std::max(1, int(double(box[a]) / cell));
            m_inverseCell[size_t(a)] = double(m_dims[size_t(a)]) / double(box[a]);
        }
        const size_t cells = size_t(m_dims[0]) * size_t(m_dims[1]) * size_t(m_dims[2]);
        m_cellStart.assign(cells + 1, 0);
        m_cellOf.resize(size_t(n));
        for (int64_t i = 0; i < n; ++i) {
            m_cellOf[size_t(i)] = cellIndex(cellCoords(x[size_t(i)]));
            ++m_cellStart[m_cellOf[size_t(i)] + 1];
        }
        for (size_t c = 0; c < cells; ++c) m_cellStart[c + 1] += m_cellStart[c];
        m_sorted.resize(size_t(n));
        std::vector<int64_t> fill(m_cellStart.begin(), m_cellStart.end() - 1);
        for (int64_t i = 0; i < n; ++i) m_sorted[size_t(fill[m_cellOf[size_t(i)]]++)] = i;
    }

    // fn(j) for every particle in the 27 cells around particle i's cell (i itself included).
    template <class Fn>
    void forNeighbours(const Vec3<Real>& position, Fn&& fn) const {
        const std::array<int, 3> c = cellCoords(position);
        for (int dz = -1; dz <= 1; ++dz)
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const std::array<int, 3> n{c[0] + dx, c[1] + dy, c[2] + dz};
                    if (n[0] < 0 || n[1] < 0 || n[2] < 0 || n[0] >= m_dims[0] || n[1] >= m_dims[1] || n[2] >= m_dims[2]) continue;
                    const size_t cell = cellIndex(n);
                    for (int64_t k = m_cellStart[cell]; k < m_cellStart[cell + 1]; ++k) fn(m_sorted[size_t(k)]);
                }
    }

private:
    std::array<int, 3> cellCoords(const Vec3<Real>& p) const {
        std::array<int, 3> c{};
        for (int a = 0; a < 3; ++a) {
            // Clamped: a particle slightly outside the box (being resolved) belongs to the edge cell.
            const double f = std::floor(double(p[a]) * m_inverseCell[size_t(a)]);
            c[size_t(a)] = int(std::min(std::max(f, 0.0), double(m_dims[size_t(a)] - 1)));
        }
        return c;
    }
    size_t cellIndex(const std::array<int, 3>& c) const {
        return (size_t(c[2]) * size_t(m_dims[1]) + size_t(c[1])) * size_t(m_dims[0]) + size_t(c[0]);
    }

    std::array<int, 3> m_dims{1, 1, 1};
    std::array<double, 3> m_inverseCell{1, 1, 1};
    std::vector<int64_t> m_cellStart;
    std::vector<size_t> m_cellOf;
    std::vector<int64_t> m_sorted;
};

}  // namespace corebox
