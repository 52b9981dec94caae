// Cell list: the one uniform grid over the box, shared by the host (src/core/host_cell_list.h: initial
// overlap checks, the CPU contact search) and the GPU (cell_list_kernels.cu: the contact search of
// collision_kernels.cu). Everything here is plain data and __host__ __device__ functions, so both sides
// size the grid by the same rule, put a position in the same cell and walk neighbours in the same order.
//
// - The rule (cellGeometry): cells at least `minCell` wide on every axis, so every pair closer than
//   minCell lies in the same or an adjacent cell, and about two cells per particle at most, so that a
//   dilute system does not pay for empty cells. Contacts pass minCell = the largest a_i + a_j of the
//   particles in the cells (below); forces with a cutoff pass r_c + skin and keep Verlet lists from the
//   same walk.
// - Layout (CellListView): particles sorted by cell key, cellStart[key] .. cellStart[key + 1] the slice
//   of cell `key` (cells + 1 entries), ascending particle index inside a cell. The host builds it by a
//   counting sort, the GPU by a stable radix sort of (key, index) pairs; both give the same arrays.
// - Order (forEachNeighbour): the 27 cells around a position (a large particle: the cells within its
//   reach) in ascending key, then ascending particle index, then the large particles in ascending
//   index, so any order-dependent sum or tie-break over neighbours is reproducible bit for bit.
// - Large particles (CellSplit): a few particles much larger than the rest would set minCell for all
//   (a heavy ball of radius 1 among 10^5 of radius 0.5 made the cells twice as wide, eight times the
//   neighbours to look at). So the particles of radius above `largeAbove` are kept out of the cells,
//   after them in the order (key = cells, so sorted[cellStart[cells] .. n)), and minCell is set by the
//   largest radius left in the cells. Every walk visits that tail; a large particle walks the cells
//   within its radius plus `largeReach` (the cell width less the largest radius in the cells: the
//   farthest a partner in the cells can be) instead of the 27 around it. Every pair is still visited
//   from both sides, and once. Which particles are large is a property of the species
//   (chooseCellSplit), so the build and the walks classify a particle alike.
// - Robustness: a position outside the box, or not finite at all, maps to a clamped valid cell (no
//   out-of-range float-to-int conversion), and the cell count stays bounded and within int32 whatever
//   the box, n and minCell are (a flat box, one huge axis, a non-finite input).
#pragma once

#include <cstdint>

#include "hd.h"
#include "vec3.h"

namespace corebox {

// Cells per axis and the inverse cell width per axis (cell coordinate = floor(x * inverseCell)).
struct CellGeometry {
    int dims[3];
    double inverseCell[3];

    COREBOX_HD int cellCount() const { return dims[0] * dims[1] * dims[2]; }
};

// At most this many cells in any grid: cellStart (cells + 1 entries) and every cell key then fit
// int32, and the arrays stay at a few GiB even for a billion-particle system.
constexpr int64_t kMaxCellCount = int64_t(1) << 30;
// Cells allowed on top of two per particle: a handful of particles still gets a small 3-D grid.
constexpr int64_t kCellCountSlack = 64;

// Cell count bound for n particles: 2n + slack, never more than kMaxCellCount.
COREBOX_HD inline int64_t maxCellCount(int64_t n) {
    const int64_t perParticle = n < 0 ? 0 : (n > kMaxCellCount ? kMaxCellCount : n);
    const int64_t bound = 2 * perParticle + kCellCountSlack;
    return bound < kMaxCellCount ? bound : kMaxCellCount;
}

namespace detail {

// floor(length / cell), at least 1 and at most kMaxCellCount, computed in double so that a huge
// ratio never reaches an int conversion; a NaN ratio (0/0, inf/inf) gives one cell.
COREBOX_HD inline double cellsAlong(double length, double cell) {
    const double d = length / cell;
    if (!(d >= 1.0)) return 1.0;
    return d < double(kMaxCellCount) ? floor(d) : double(kMaxCellCount);
}

COREBOX_HD inline double cellProduct(const Vec3<double>& box, double cell) {
    return cellsAlong(box.x, cell) * cellsAlong(box.y, cell) * cellsAlong(box.z, cell);
}

}  // namespace detail

// The one cell-size rule. cell = max(minCell, cbrt(volume / (2n))) and dims = max(1, floor(L / cell))
// per axis: the density term keeps about two cells per particle. When an axis is shorter than one
// cell (a flat box) the others would get more cells than that (L_x L_y / cell^2 = 2n cell / L_z), and
// a huge axis would overflow int: then the cell grows, by bisection, to (within double precision)
// the smallest size whose grid has at most maxCellCount(n) cells. A larger cell keeps every pair
// closer than minCell in adjacent cells, so the bound costs speed at worst, never a missed pair.
COREBOX_HD inline CellGeometry cellGeometry(const Vec3<double>& box, int64_t n, double minCell) {
    const double volume = box.x * box.y * box.z;
    const double byDensity = cbrt(volume / double(n > 0 ? 2 * n : 1));
    // NaN-tolerant max: a NaN density term leaves minCell; a NaN minCell yields one cell per axis.
    double cell = minCell < byDensity ? byDensity : minCell;
    const double bound = double(maxCellCount(n));
    if (detail::cellProduct(box, cell) > bound) {
        // At the longest edge every axis has one cell, which satisfies any bound.
        double lo = cell;
        double hi = box.x > box.y ? box.x : box.y;
        hi = hi > box.z ? hi : box.z;
        for (int k = 0; k < 128 && lo < hi; ++k) {
            const double mid = lo + 0.5 * (hi - lo);
            if (mid <= lo || mid >= hi) break;
            if (detail::cellProduct(box, mid) > bound) lo = mid;
            else hi = mid;
        }
        cell = hi;
    }
    CellGeometry g{};
    for (int a = 0; a < 3; ++a) {
        g.dims[a] = int(detail::cellsAlong(box[a], cell));
        g.inverseCell[a] = double(g.dims[a]) / box[a];
    }
    return g;
}

struct CellCoords {
    int x, y, z;
};

// Cell coordinate on one axis, clamped to [0, dim): a particle slightly outside the box (being
// resolved) belongs to the edge cell. Written so that NaN (fails f >= 0) and +-inf land on a valid
// cell without a float-to-int conversion out of range, which would be undefined behaviour.
template <class Real>
COREBOX_HD inline int cellCoord(Real position, double inverseCell, int dim) {
    const double f = double(position) * inverseCell;
    if (!(f >= 0.0)) return 0;
    if (f >= double(dim)) return dim - 1;
    return int(f);
}

template <class Real>
COREBOX_HD inline CellCoords cellCoords(const CellGeometry& g, const Vec3<Real>& p) {
    return CellCoords{cellCoord(p.x, g.inverseCell[0], g.dims[0]), cellCoord(p.y, g.inverseCell[1], g.dims[1]),
                      cellCoord(p.z, g.inverseCell[2], g.dims[2])};
}

// x fastest, then y, then z: ascending keys walk the grid row by row.
COREBOX_HD inline int cellKey(const CellGeometry& g, CellCoords c) { return (c.z * g.dims[1] + c.y) * g.dims[0] + c.x; }

template <class Real>
COREBOX_HD inline int cellKeyOf(const CellGeometry& g, const Vec3<Real>& p) {
    return cellKey(g, cellCoords(g, p));
}

// fn(key) for the up to 27 cells around c that exist, in ascending key.
template <class Fn>
COREBOX_HD inline void forEachNeighbourCell(const CellGeometry& g, CellCoords c, Fn&& fn) {
    for (int z = c.z - 1; z <= c.z + 1; ++z) {
        if (z < 0 || z >= g.dims[2]) continue;
        for (int y = c.y - 1; y <= c.y + 1; ++y) {
            if (y < 0 || y >= g.dims[1]) continue;
            for (int x = c.x - 1; x <= c.x + 1; ++x) {
                if (x < 0 || x >= g.dims[0]) continue;
                fn(cellKey(g, CellCoords{x, y, z}));
            }
        }
    }
}

// The 27 cells around c as 9 runs of consecutive keys (x is fastest): run r in [0, 9) is the row at
// z = c.z - 1 + r / 3, y = c.y - 1 + r % 3, its cells x = c.x - 1 .. c.x + 1 clipped to the grid, keys
// [*first, *last]. False where that row lies outside the grid. A cell list's particles of a run are
// one contiguous range of its order (cellStart[*first] .. cellStart[*last + 1]).
COREBOX_HD inline bool neighbourCellRun(const CellGeometry& g, CellCoords c, int r, int* first, int* last) {
    const int z = c.z - 1 + r / 3, y = c.y - 1 + r % 3;
    if (z < 0 || z >= g.dims[2] || y < 0 || y >= g.dims[1]) return false;
    const int x0 = c.x > 0 ? c.x - 1 : 0;
    const int x1 = c.x + 1 < g.dims[0] ? c.x + 1 : g.dims[0] - 1;
    *first = cellKey(g, CellCoords{x0, y, z});
    *last = cellKey(g, CellCoords{x1, y, z});
    return true;
}

// No particle is kept out of the cells (CellSplit::largeAbove).
constexpr double kNoLargeParticles = 1e300;

// Which particles a build keeps out of the cells (design note): those whose species' radius is above
// largeAbove, which lies between two species' radii (chooseCellSplit), so a float radius and its
// double agree on it. No species: none.
template <class Real>
struct CellSplit {
    const int32_t* species = nullptr;  // n species indices
    const Real* radius = nullptr;      // per species [sigma]
    double largeAbove = kNoLargeParticles;
};

// The threshold a split keeps out of the cells: none without species.
template <class Real>
inline double largeAboveOf(const CellSplit<Real>& split) {
    return split.species ? split.largeAbove : kNoLargeParticles;
}

// The cell key of particle i at x: its cell, or cells for a particle kept out of them.
template <class Real>
COREBOX_HD inline int cellKeyOfParticle(const CellGeometry& g, const CellSplit<Real>& split, int64_t i, const Vec3<Real>& x) {
    if (split.species && double(split.radius[split.species[i]]) > split.largeAbove) return g.cellCount();
    return cellKeyOf(g, x);
}

// Whether two geometries are the same grid.
COREBOX_HD inline bool sameGeometry(const CellGeometry& a, const CellGeometry& b) {
    for (int k = 0; k < 3; ++k)
        if (a.dims[k] != b.dims[k] || a.inverseCell[k] != b.inverseCell[k]) return false;
    return true;
}

// How far beyond its radius a large particle's walk reaches (CellListView::largeReach) [sigma]: the
// narrowest cell less the largest radius in the cells, over the axes of more than one cell (an axis of
// one cell, narrower than minCell in a thin box, is walked whole anyway; none: the box's widest edge),
// plus a millionth of the box's widest edge, so that the pairs a float distance puts within reach are
// in it from the large particle's side too (the small one's walk visits every large particle).
inline double largeReachOf(const CellGeometry& g, double gridRadius) {
    double narrowest = 0, widest = 0;
    for (int a = 0; a < 3; ++a) {
        const double width = 1.0 / g.inverseCell[a], edge = width * g.dims[a];
        widest = edge > widest ? edge : widest;
        if (g.dims[a] > 1 && (narrowest == 0 || width < narrowest)) narrowest = width;
    }
    return (narrowest > 0 ? narrowest - gridRadius : widest) + 1e-6 * widest;
}

// A built cell list, owned elsewhere (host vectors or device buffers).
struct CellListView {
    CellGeometry geometry;
    const int32_t* cellStart;  // cells + 1: cell k holds sorted[cellStart[k] .. cellStart[k + 1])
    const int32_t* sorted;     // n particle indices by ascending (cell key, index)
    // Particles of radius above this are not in the cells but at sorted[cellStart[cells] .. count), and
    // their partners in the cells lie within their radius plus largeReach [sigma].
    double largeAbove = kNoLargeParticles;
    double largeReach = 0;
    int32_t count = 0;  // n, where a split is made
};

// The view of a build over n particles with `split`: largeReach from the cells' width and the largest
// radius left in them (chooseCellSplit's gridRadius).
inline CellListView splitView(CellListView view, double largeAbove, double gridRadius, int64_t n) {
    view.largeAbove = largeAbove;
    view.largeReach = largeAbove < kNoLargeParticles ? largeReachOf(view.geometry, gridRadius) : 0.0;
    view.count = int32_t(n);
    return view;
}

COREBOX_HD inline bool isLargeIn(const CellListView& view, double radius) { return radius > view.largeAbove; }

// fn(j) for every particle j in the 27 cells around `position` (the particle itself included when it
// is in the list), in ascending cell key and, within a cell, ascending index, then for every large
// particle. Every particle closer to `position` than the minCell the geometry was made with is
// visited exactly once, up to the rounding of x * inverseCell: a pair across a cell face closer than
// minCell by less than ~1e-16 of its cell coordinate may be missed, which the contact and overlap
// tests ignore anyway (their relative slack is 1e-12 or more).
// With a split, `radius` is that of the particle at `position`: a large one walks the cells within its
// reach, every one then the large particles (the tail, in ascending index). The cells are walked as
// rows of consecutive keys (x is fastest), each one contiguous range of the order, and the tail as one
// more range: one loop, so that `fn` is inlined once (two walks, each with its own copy of a search's
// body, made the CPU's impact search 40% slower).
template <class Real, class Fn>
COREBOX_HD inline void forEachNeighbour(const CellListView& view, const Vec3<Real>& position, Real radius, Fn&& fn) {
    const CellGeometry& g = view.geometry;
    int lo[3], hi[3];
    if (isLargeIn(view, double(radius))) {
        const double reach = double(radius) + view.largeReach;
        for (int a = 0; a < 3; ++a) {
            lo[a] = cellCoord(double(position[a]) - reach, g.inverseCell[a], g.dims[a]);
            hi[a] = cellCoord(double(position[a]) + reach, g.inverseCell[a], g.dims[a]);
        }
    } else {
        const CellCoords c = cellCoords(g, position);
        const int at[3] = {c.x, c.y, c.z};
        for (int a = 0; a < 3; ++a) {
            lo[a] = at[a] > 0 ? at[a] - 1 : 0;
            hi[a] = at[a] + 1 < g.dims[a] ? at[a] + 1 : g.dims[a] - 1;
        }
    }
    const int rowsY = hi[1] - lo[1] + 1;
    const int rows = (hi[2] - lo[2] + 1) * rowsY;
    const bool tail = view.largeAbove < kNoLargeParticles;
    for (int r = 0; r <= rows; ++r) {
        int32_t begin = 0, end = 0;
        if (r < rows) {
            const int z = lo[2] + r / rowsY, y = lo[1] + r % rowsY;
            begin = view.cellStart[cellKey(g, CellCoords{lo[0], y, z})];
            end = view.cellStart[cellKey(g, CellCoords{hi[0], y, z}) + 1];
        } else if (tail) {
            begin = view.cellStart[g.cellCount()];
            end = view.count;
        }
        for (int32_t k = begin; k < end; ++k) fn(int64_t(view.sorted[k]));
    }
}

// The walk of a particle in the cells (not a large one).
template <class Real, class Fn>
COREBOX_HD inline void forEachNeighbour(const CellListView& view, const Vec3<Real>& position, Fn&& fn) {
    forEachNeighbour(view, position, Real(0), fn);
}

}  // namespace corebox
