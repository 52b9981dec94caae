// A uniform grid over the World's host mirror: which slots lie near a point. It serves the two
// host-side questions of the library, "would a particle placed here overlap another?" (add and
// teleport) and "which particles lie within r of a point?" (picking), without an O(N) scan each.
//
// Cells are at least `minCell` wide (the largest contact distance, so an overlap check visits the 27
// cells around a point) and tile the box, whose walls keep every particle inside it: a dense array of
// cell heads and a next-slot link per slot (a chain per cell). Building is one pass over the slots,
// and an add links one more slot in. The grid is rebuilt from the mirror after a step (the particles
// moved) or a removal (slots were compacted), so the build is what an edit after a step costs: at
// 10^5 balls a hash map of per-cell vectors took 20 to 25 ms for it (this 2-core EPYC), the chains
// 1 to 2 ms. The cells are made wider where the box would need more than max(2 N, 2^16) of them, so a
// large box does not cost memory beyond the particles'.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "corebox/world.h"

namespace corebox {

class SlotGrid {
public:
    // Every slot of `x` in cells at least `minCell` wide over the box [0, box] on each axis.
    void build(const std::vector<Vec3d>& x, double minCell, const Vec3d& box) {
        const double edge[3] = {box.x, box.y, box.z};
        const double cap = std::max(2.0 * double(x.size()), 65536.0);
        m_cell = std::max(minCell, 1e-9);
        for (;;) {
            double cells = 1;
            for (int a = 0; a < 3; ++a) cells *= std::max(1.0, std::ceil(edge[a] / m_cell));
            if (cells <= cap) break;
            m_cell *= 1.25;
        }
        for (int a = 0; a < 3; ++a) m_dims[a] = int64_t(std::max(1.0, std::ceil(edge[a] / m_cell)));
        m_head.assign(size_t(m_dims[0] * m_dims[1] * m_dims[2]), kNone);
        m_next.assign(x.size(), kNone);
        for (uint32_t slot = 0; slot < uint32_t(x.size()); ++slot) insert(slot, x[slot]);
    }

    // Links one more slot in (slots come in order: an add's slot is the next one).
    void insert(uint32_t slot, const Vec3d& x) {
        if (m_head.empty()) return;  // not built: the next build takes every slot
        if (slot >= m_next.size()) m_next.resize(size_t(slot) + 1, kNone);
        const size_t c = cellOf(clamped(x.x, 0), clamped(x.y, 1), clamped(x.z, 2));
        m_next[slot] = m_head[c];
        m_head[c] = int32_t(slot);
    }

    // fn(slot) for every slot in the cells within `reach` of x (a superset of the slots within reach).
    template <class Fn>
    void forNear(const Vec3d& x, double reach, Fn&& fn) const {
        if (m_head.empty() || !(reach >= 0) || !std::isfinite(x.x) || !std::isfinite(x.y) || !std::isfinite(x.z)) return;
        const double at[3] = {x.x, x.y, x.z};
        int64_t lo[3], hi[3];
        for (int a = 0; a < 3; ++a) {
            // Unclamped, then cut to the grid: a point outside the box still finds the particles near it.
            const double limit = double(m_dims[a]);
            lo[a] = int64_t(std::clamp(std::floor((at[a] - reach) / m_cell), 0.0, limit));
            hi[a] = int64_t(std::clamp(std::floor((at[a] + reach) / m_cell), -1.0, limit - 1));
            if (lo[a] > hi[a]) return;
        }
        for (int64_t i = lo[0]; i <= hi[0]; ++i)
            for (int64_t j = lo[1]; j <= hi[1]; ++j)
                for (int64_t k = lo[2]; k <= hi[2]; ++k)
                    for (int32_t s = m_head[cellOf(i, j, k)]; s != kNone; s = m_next[size_t(s)]) fn(uint32_t(s));
    }
    double cell() const { return m_cell; }

private:
    static constexpr int32_t kNone = -1;
    int64_t clamped(double v, int axis) const {
        const double c = std::floor(v / m_cell);
        return !(c > 0) ? 0 : int64_t(std::min(c, double(m_dims[axis] - 1)));
    }
    size_t cellOf(int64_t i, int64_t j, int64_t k) const { return size_t((k * m_dims[1] + j) * m_dims[0] + i); }

    double m_cell = 1;
    int64_t m_dims[3] = {1, 1, 1};
    std::vector<int32_t> m_head;  // per cell: its last slot linked in, or kNone
    std::vector<int32_t> m_next;  // per slot: the slot linked in before it in its cell, or kNone
};

}  // namespace corebox
