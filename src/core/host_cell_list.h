// Host side of the one cell list (kernels/cell_list.h): the owning arrays behind a CellListView,
// built from positions by a counting sort. Counting the particles of each cell, prefix-summing the
// counts into cellStart and then scattering indices in ascending order gives ascending indices inside
// every cell, the same arrays the GPU's stable radix sort produces, with no dependence on thread
// count. Used by the CPU backend's contact search (rebuilt every collision round, since resolution
// moves particles) and by the initial overlap check.
//
// (Named host_cell_list.h, not cell_list.h: src/core and kernels/ are both on the include path, and
// this header includes kernels/cell_list.h, which a same-named file would shadow.)
//
// IncrementalCellList serves random placement, which asks "is this spot free?" of a set that grows
// by one particle at a time: a sorted list would need a rebuild per insertion, so it keeps a linked
// list per cell instead, with the same geometry, the same rule and the same visiting order.
#pragma once

#include <cstdint>
#include <vector>

#include "cell_list.h"
#include "vec3.h"

namespace corebox {

// Which particles a contact grid keeps out of its cells (cell_list.h: large particles), from each
// species' radius and particle count: the smallest radius with at most kMaxLargeParticles particles
// above it stays in the cells (gridRadius), the species above it are large; none when the largest
// radius is less than kLargeRatio times that (the cells would narrow by little). Every species of a
// larger radius is large, present or not, so a particle added later is never in cells too narrow for
// it; the counts only decide what is fast.
struct CellSplitChoice {
    double gridRadius = 0;                   // the largest radius in the cells [sigma]: minCell = 2 gridRadius (+ gaps)
    double largeAbove = kNoLargeParticles;   // radii above it are kept out of the cells
};
constexpr int64_t kMaxLargeParticles = 64;  // each walk visits them all
constexpr double kLargeRatio = 1.25;
CellSplitChoice chooseCellSplit(const std::vector<double>& radius, const std::vector<int64_t>& count);

// The split a choice makes over particles' species and the radii per species (host or device
// pointers): none where it keeps no particle out.
template <class Real>
CellSplit<Real> cellSplitOf(const CellSplitChoice& choice, const int32_t* species, const Real* radius) {
    if (!(choice.largeAbove < kNoLargeParticles)) return CellSplit<Real>{};
    return CellSplit<Real>{species, radius, choice.largeAbove};
}

// Particles per species (species indices outside [0, species) are not counted).
std::vector<int64_t> speciesCounts(const std::vector<int32_t>& species, int speciesCount);

class CellList {
public:
    // Builds over x with the one rule: cells at least minCell wide (contacts: the largest a_i + a_j).
    template <class Real>
    void build(const std::vector<Vec3<Real>>& x, const Vec3<Real>& box, double minCell) {
        const int64_t n = int64_t(x.size());
        build(x.data(), n, cellGeometry(vec3Cast<double>(box), n, minCell));
    }
    // Builds over x[0 .. n) with a given geometry. Throws std::length_error when n exceeds int32.
    template <class Real>
    void build(const Vec3<Real>* x, int64_t n, const CellGeometry& geometry) {
        build(x, n, geometry, CellSplit<Real>{}, 0.0);
    }
    // The same, keeping the particles `split` names out of the cells (after them in the order);
    // gridRadius: the largest radius left in the cells (chooseCellSplit).
    template <class Real>
    void build(const Vec3<Real>* x, int64_t n, const CellGeometry& geometry, const CellSplit<Real>& split, double gridRadius);

    // fn(j) for every particle in the 27 cells around `position` and the large particles, or for a
    // large particle of this radius the cells within its reach (see forEachNeighbour).
    template <class Real, class Fn>
    void forNeighbours(const Vec3<Real>& position, Real radius, Fn&& fn) const {
        forEachNeighbour(view(), position, radius, fn);
    }
    template <class Real, class Fn>
    void forNeighbours(const Vec3<Real>& position, Fn&& fn) const {
        forEachNeighbour(view(), position, fn);
    }

    CellListView view() const {
        CellListView v{m_geometry, m_cellStart.data(), m_sorted.data()};
        v.largeAbove = m_largeAbove;  // what splitView gave at the build: a walk a particle asks for the view
        v.largeReach = m_largeReach;
        v.count = int32_t(m_sorted.size());
        return v;
    }
    const CellGeometry& geometry() const { return m_geometry; }
    // cells + 1 offsets into sorted(); n particle indices by ascending (cell key, index).
    const std::vector<int32_t>& cellStart() const { return m_cellStart; }
    const std::vector<int32_t>& sorted() const { return m_sorted; }

private:
    // Empty until built: one cell, no particles, so forNeighbours visits nothing.
    CellGeometry m_geometry{{1, 1, 1}, {1.0, 1.0, 1.0}};
    std::vector<int32_t> m_cellStart{0, 0};
    std::vector<int32_t> m_sorted;
    std::vector<int32_t> m_cellOf;  // scratch of build: each particle's cell key
    double m_largeAbove = kNoLargeParticles, m_largeReach = 0;
};

class IncrementalCellList {
public:
    // Room for indices [0, capacity); geometry from cellGeometry (see CellList::build).
    IncrementalCellList(const CellGeometry& geometry, int64_t capacity);

    // Indices must be inserted in ascending order, so that a cell's list stays ascending.
    void insert(int64_t index, const Vec3<double>& position);

    template <class Fn>
    void forNeighbours(const Vec3<double>& position, Fn&& fn) const {
        forEachNeighbourCell(m_geometry, cellCoords(m_geometry, position), [&](int cell) {
            for (int64_t j = m_head[size_t(cell)]; j >= 0; j = m_next[size_t(j)]) fn(j);
        });
    }

private:
    CellGeometry m_geometry;
    std::vector<int64_t> m_head, m_tail;  // per cell: first and last index, -1 when empty
    std::vector<int64_t> m_next;          // per index: next index in its cell, -1 at the end
};

}  // namespace corebox
