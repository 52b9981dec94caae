// The 27-cell neighbour walk of cell_list.h (forEachNeighbour) shared by a group of G consecutive lanes
// of a warp, for searches whose particles are few: a thread per particle walks its 27 cells alone, and
// at N = 1024 (4 blocks) the collision search took 14 us on an H200 (ncu), all of it one thread's
// latency; 8 lanes walking the cells in turn took 9 us, 32 lanes with the cells' bounds loaded at once
// 7 to 8 us (a search that finds nothing to do, 2 us: the rest is the chain of dependent loads). A group of G
// visits the same particles, each exactly once by one of its lanes, in another order; what the
// searches take from the walk does not depend on the order (the earliest event by a total order,
// collision_resolution.h isBetter; a count), so the results are those of the walk alone, bit for bit.
#pragma once

#include <cuda_runtime.h>

#include <cstdint>

#include "cell_list.h"

namespace corebox::gpu {

// Lanes a particle a search gives its particles, by their number: a thread alone for many (the walks
// of a warp's threads then overlap in the caches), a group where they are few enough that one thread's
// walk would be the whole search's latency. Tried and not kept: the impact search (findEventsKernel) with
// 2 or 4 lanes a particle up to 131,072 particles: the sandbox example at 10^5 balls took 3.87 / 3.86 and
// 4.05 / 4.04 ms a frame in its impacts against 3.56 / 3.72 with one (the same state hash), the
// 10^5-ball pile 8.27 and 8.21 ms a frame against 8.10 (an H200, fp32, one call).
inline int searchGroupFor(int64_t n) { return n <= 4096 ? 32 : n <= 32768 ? 8 : 1; }

// The lanes of the calling thread's group of G in its warp (G a power of two dividing 32).
template <int G>
__device__ inline unsigned groupMask() {
    const unsigned lane = threadIdx.x % 32u;
    return unsigned(((1ull << G) - 1ull) << (lane / G * G));
}

// fn(j) for the particles of the 27 cells around `position` (and the large ones: below) whose place in
// the walk's concatenated runs (cell_list.h neighbourCellRun: 9 rows of up to 3 cells, each one
// contiguous range of the list's order) is rank modulo G. The runs' bounds are loaded first, all at
// once (independent loads), then each lane takes its places: a few dependent loads deep, whatever the
// number of cells.
// With a split (cell_list.h), `radius` is the particle's: a large particle's wider walk is made by its
// first lane alone (they are few), the large particles' tail is shared out like the runs.
template <int G, class Real, class Fn>
__device__ inline void forEachNeighbourShared(const CellListView& view, const Vec3<Real>& position, Real radius, int rank, Fn&& fn) {
    if (view.largeAbove < kNoLargeParticles) {
        if (isLargeIn(view, double(radius))) {
            if (rank == 0) forEachNeighbour(view, position, radius, fn);
            return;
        }
        const int32_t tail = view.cellStart[view.geometry.cellCount()];
        for (int32_t k = tail + rank; k < view.count; k += G) fn(int64_t(view.sorted[k]));
    }
    const CellCoords c = cellCoords(view.geometry, position);
    int32_t begin[9], length[9];
#pragma unroll
    for (int r = 0; r < 9; ++r) {
        int first = 0, last = 0;
        const bool inside = neighbourCellRun(view.geometry, c, r, &first, &last);
        begin[r] = inside ? view.cellStart[first] : 0;
        length[r] = inside ? view.cellStart[last + 1] - begin[r] : 0;
    }
    int32_t placed = 0;  // places in the runs before run r
#pragma unroll
    for (int r = 0; r < 9; ++r) {
        const int32_t skip = ((rank - placed) % G + G) % G;
        for (int32_t k = skip; k < length[r]; k += G) fn(int64_t(view.sorted[begin[r] + k]));
        placed += length[r];
    }
}

}  // namespace corebox::gpu
