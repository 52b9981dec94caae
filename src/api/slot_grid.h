// A uniform grid over the World's host mirror: which slots lie near a point. It serves the two
// host-side questions of the library, "would a particle placed here overlap another?" (add and
// teleport) and "which particles lie within r of a point?" (picking), without an O(N) scan each.
//
// Cells are at least `minCell` wide (the largest contact distance, so an overlap check visits the 27
// cells around a point) and tile the particles' bounding box: a dense array of cell heads and a
// next-slot link per slot (a chain per cell). Building is one pass over the slots, and an add links one
// more slot in (a point outside the tiled region goes to the nearest border cell, which a query near it
// still visits). The grid is rebuilt from the mirror after a step (the particles moved), a removal
// (slots were compacted), or when adds have more than doubled the slots it was built for
// (`outgrown`), so the build is what an edit after a step costs: at 10^5 balls a hash map of per-cell
// vectors took 20 to 25 ms for it (this 2-core EPYC), the chains 1 to 2 ms. The cells are made wider
// where the bounding box would need more than max(2 N, 2^16) of them, so memory stays within the
// particles' count; tiling the bounding box rather than the box keeps a cluster in a large box in
// fine cells.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "corebox/world.h"

namespace corebox {

class SlotGrid {
public:
    // Every slot of `x` in cells at least `minCell` wide over the slots' bounding box.
    void build(const std::vector<Vec3d>& x, double minCell) {
        double lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
        for (size_t k = 0; k < x.size(); ++k) {
            const double at[3] = {x[k].x, x[k].y, x[k].z};
            for (int a = 0; a < 3; ++a) {
                if (!std::isfinite(at[a])) continue;
                lo[a] = k == 0 ? at[a] : std::min(lo[a], at[a]);
                hi[a] = k == 0 ? at[a] : std::max(hi[a], at[a]);
            }
        }
        const double cap = std::max(2.0 * double(x.size()), 65536.0);
        m_cell = std::max(minCell, 1e-9);
        for (;;) {
            double cells = 1;
            for (int a = 0; a < 3; ++a) cells *= std::floor((hi[a] - lo[a]) / m_cell) + 1;
            if (cells <= cap) break;
            m_cell *= 1.25;
        }
        for (int a = 0; a < 3; ++a) {
            m_origin[a] = lo[a];
            m_dims[a] = int64_t(std::floor((hi[a] - lo[a]) / m_cell)) + 1;
        }
        m_head.assign(size_t(m_dims[0] * m_dims[1] * m_dims[2]), kNone);
        m_next.assign(x.size(), kNone);
        m_builtFor = x.size();
        for (uint32_t slot = 0; slot < uint32_t(x.size()); ++slot) insert(slot, x[slot]);
    }

    // Links one more slot in (slots come in order: an add's slot is the next one).
    void insert(uint32_t slot, const Vec3d& x) {
        if (m_head.empty()) return;  // not built: the next build takes every slot
        if (slot >= m_next.size()) m_next.resize(size_t(slot) + 1, kNone);
        const size_t c = cellOf(clamped(x.x, 0), clamped(x.y, 1), clamped(x.z, 2));
        m_next[slot] = m_head[c];
        m_head[c] = slot;
    }

    // Adds have more than doubled the slots since the build: the cells may no longer suit them.
    bool outgrown(size_t slots) const { return slots > 2 * m_builtFor + 64; }

    // fn(slot) for every slot in the cells within `reach` of x (a superset of the slots within reach).
    template <class Fn>
    void forNear(const Vec3d& x, double reach, Fn&& fn) const {
        if (m_head.empty() || !(reach >= 0) || !std::isfinite(x.x) || !std::isfinite(x.y) || !std::isfinite(x.z)) return;
        const double at[3] = {x.x, x.y, x.z};
        int64_t lo[3], hi[3];
        for (int a = 0; a < 3; ++a) {
            // Cut to the grid: a point beyond the tiled region visits the border cells within reach,
            // where the slots beyond it were linked in.
            const double last = double(m_dims[a] - 1);
            const double from = std::floor((at[a] - reach - m_origin[a]) / m_cell);
            const double to = std::floor((at[a] + reach - m_origin[a]) / m_cell);
            if (to < 0) {
                lo[a] = hi[a] = 0;  // wholly below: the border cell
            } else if (from > last) {
                lo[a] = hi[a] = m_dims[a] - 1;  // wholly above
            } else {
                lo[a] = int64_t(std::clamp(from, 0.0, last));
                hi[a] = int64_t(std::clamp(to, 0.0, last));
            }
        }
        for (int64_t i = lo[0]; i <= hi[0]; ++i)
            for (int64_t j = lo[1]; j <= hi[1]; ++j)
                for (int64_t k = lo[2]; k <= hi[2]; ++k)
                    for (uint32_t s = m_head[cellOf(i, j, k)]; s != kNone; s = m_next[size_t(s)]) fn(s);
    }

private:
    static constexpr uint32_t kNone = std::numeric_limits<uint32_t>::max();  // the World's slots stay below it
    int64_t clamped(double v, int axis) const {
        const double c = std::floor((v - m_origin[axis]) / m_cell);
        return !(c > 0) ? 0 : int64_t(std::min(c, double(m_dims[axis] - 1)));
    }
    size_t cellOf(int64_t i, int64_t j, int64_t k) const { return size_t((k * m_dims[1] + j) * m_dims[0] + i); }

    double m_cell = 1;
    double m_origin[3] = {0, 0, 0};
    int64_t m_dims[3] = {1, 1, 1};
    size_t m_builtFor = 0;
    std::vector<uint32_t> m_head;  // per cell: its last slot linked in, or kNone
    std::vector<uint32_t> m_next;  // per slot: the slot linked in before it in its cell, or kNone
};

}  // namespace corebox
