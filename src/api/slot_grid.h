// A uniform hash grid over the World's host mirror: which slots lie near a point. It serves the two
// host-side questions of the library, "would a particle placed here overlap another?" (add and
// teleport) and "which particles lie within r of a point?" (picking), without an O(N) scan each.
//
// Cells are `cell` wide (at least the largest contact distance, so an overlap check visits the 27
// cells around a point) and hashed by their integer coordinates, so the box size does not bound the
// memory. Slots are inserted one at a time (adds) and the grid is rebuilt from the mirror when the
// particles moved (a step) or slots were compacted (a removal).
#pragma once

#include <cmath>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "corebox/world.h"

namespace corebox {

class SlotGrid {
public:
    void reset(double cell) {
        m_cell = cell;
        m_cells.clear();
    }
    void insert(uint32_t slot, const Vec3d& x) { m_cells[keyOf(coord(x.x), coord(x.y), coord(x.z))].push_back(slot); }

    // fn(slot) for every slot in the cells within `reach` of x (a superset of the slots within reach).
    template <class Fn>
    void forNear(const Vec3d& x, double reach, Fn&& fn) const {
        const int64_t span = int64_t(std::ceil(reach / m_cell));
        const int64_t cx = coord(x.x), cy = coord(x.y), cz = coord(x.z);
        for (int64_t i = cx - span; i <= cx + span; ++i) {
            for (int64_t j = cy - span; j <= cy + span; ++j) {
                for (int64_t k = cz - span; k <= cz + span; ++k) {
                    const auto it = m_cells.find(keyOf(i, j, k));
                    if (it == m_cells.end()) continue;
                    for (uint32_t slot : it->second) fn(slot);
                }
            }
        }
    }
    double cell() const { return m_cell; }

private:
    int64_t coord(double v) const { return int64_t(std::floor(v / m_cell)); }
    // 21 bits per axis: boxes up to 10^6 cells along an axis hash without collisions; beyond that
    // distinct cells may share a bucket, which costs time, never a wrong answer (callers test distance).
    static uint64_t keyOf(int64_t i, int64_t j, int64_t k) {
        const uint64_t mask = (uint64_t(1) << 21) - 1;
        return (uint64_t(i) & mask) | ((uint64_t(j) & mask) << 21) | ((uint64_t(k) & mask) << 42);
    }

    double m_cell = 1;
    std::unordered_map<uint64_t, std::vector<uint32_t>> m_cells;
};

}  // namespace corebox
