// The impact searches' walk over a particle's candidates (gpu_launch.h CandidateRows: the design
// note), or over the cells around it where the rounds have no rows. Every walk visits a superset of
// the particles the particle overlaps, the particle itself perhaps among them; the searches take from
// it what does not depend on the order (the earliest event by a total order, offers by atomicMax), so
// either walk gives the same bits.
#pragma once

#include "gpu_launch.h"
#include "neighbour_walk.cuh"

namespace corebox::gpu {

// fn(j) for particle i's candidates: its row, or where the row overflowed the cells of the rows' build
// around xBuilt[i]; without rows, the cells around `position` (the particle's own).
template <class Real, class Fn>
__device__ inline void forEachCandidate(const CellListView& grid, const CandidateRows<Real>& c, int64_t i,
                                        const Vec3<Real>& position, Real radius, Fn&& fn) {
    if (!c.rows) {
        forEachNeighbour(grid, position, radius, fn);
        return;
    }
    const int32_t count = c.counts[i];
    if (count > c.slots) {
        forEachNeighbour(grid, c.xBuilt[i], radius, fn);
        return;
    }
    const int32_t* row = c.rows + size_t(i) * size_t(c.slots);
    for (int32_t k = 0; k < count; ++k) fn(int64_t(row[k]));
}

// The same shared by the G lanes of a group (neighbour_walk.cuh forEachNeighbourShared): the lane of
// rank `rank` takes the row's entries k = rank (mod G).
template <int G, class Real, class Fn>
__device__ inline void forEachCandidateShared(const CellListView& grid, const CandidateRows<Real>& c, int64_t i,
                                              const Vec3<Real>& position, Real radius, int rank, Fn&& fn) {
    if (!c.rows) {
        forEachNeighbourShared<G>(grid, position, radius, rank, fn);
        return;
    }
    const int32_t count = c.counts[i];
    if (count > c.slots) {
        forEachNeighbourShared<G>(grid, c.xBuilt[i], radius, rank, fn);
        return;
    }
    const int32_t* row = c.rows + size_t(i) * size_t(c.slots);
    for (int32_t k = rank; k < count; k += G) fn(int64_t(row[k]));
}

// Whether particle i at x has moved too far from where the rows were made for them to hold (or is not
// finite).
template <class Real>
__device__ inline bool leftCandidates(const CandidateRows<Real>& c, int64_t i, const Vec3<Real>& x) {
    return !(norm2(x - c.xBuilt[i]) <= c.halfMargin2);
}

}  // namespace corebox::gpu
