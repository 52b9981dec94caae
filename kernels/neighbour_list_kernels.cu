// Neighbour lists on the GPU (gpu_launch.h: NeighbourListArgs) and the forces summed over them.
//
// Design note. The build walks the 27 cells around each row's particle (cell_list.h, the one grid,
// cells of at least r_c + skin; the candidates read from a cell-ordered copy of the positions, which
// streams: gathering x[sorted[k]] made the build 5.5 ms at 10^6 particles on an H200, most of it
// scattered loads) and keeps every partner closer than r_c + skin: full lists, so each
// row sums its own pairs with no atomics on forces and the same result on every run (Newton's third
// law would need scattered writes). A thread walks a row in large systems, a warp in small ones
// (buildListRowsKernel, buildListWarpsKernel: each the faster where it is used). Rows are sorted in
// shared memory by (partner % lanes, partner), lanes being the threads the force pass gives a row
// (listLanes): each lane's partners in ascending order, so a row's sum does not depend on when the
// list was built (a listed pair beyond the cutoff adds an exact zero to its lane), and a run restarted
// from a checkpoint, whose lists are built afresh, goes on bit for bit, as on the CPU
// (src/cpu/verlet_list.h). The lists are column-major
// (partner c of row r at c * rows + r), so a warp's loads of one column are contiguous. They are
// rebuilt when some row has moved more than skin / 2 since the build (launchListMoved, or the step
// check's forecast; src/cuda/device_neighbour_list.h), and grow when a row has more partners than
// the columns allow.
// Tried and measured slower on an H200 (LJ liquid, fp32), so not done: an aligned 16-byte copy of x
// for the force pass's partner reads (0.49 against 0.41 ms a pass at 10^6: the copy costs more than
// the wider loads save); build cells of half the reach walked 5 x 5 x 5 (fewer candidates, but rows
// in the finer cells' order slowed the force pass: 10^7 particles 10.5 against 9.7 ms a step; at
// 64000 the warp build took 207 against 211 us, its issue slots 85% busy: bound by instructions, not
// by the candidates' loads, and the pass took 43 against 41 us).
// A full pass at the end of a Verlet step also screens the collision stage (screenRow below,
// src/cuda/cuda_collisions.cpp: screenStage).
#include <cuda_runtime.h>

#include "gpu_common.cuh"
#include "gpu_launch.h"
#include "rk_stage.h"
#include "step_check.cuh"
#include "block_sums.cuh"

namespace corebox::gpu {
namespace {

// The warp build's sort key of partner j with kLanes lanes (4 or 8): the residue j % kLanes in the top
// bits, j / kLanes below, which orders by (j % kLanes, j) in shifts alone, keys distinct for
// j < 2^(31 - log2 kLanes) (the warp build serves n <= 524288, gpu_launch.h listLanes); and back.
template <int kLanes>
constexpr int laneBits() {
    static_assert(kLanes == 4 || kLanes == 8, "the warp build's lane counts");
    return kLanes == 8 ? 3 : 2;
}
template <int kLanes>
__device__ inline int32_t laneKey(int32_t j) {
    constexpr int kBits = laneBits<kLanes>();
    return int32_t((unsigned(j) & unsigned(kLanes - 1)) << (31 - kBits) | (unsigned(j) >> kBits));
}
template <int kLanes>
__device__ inline int32_t partnerOfKey(int32_t key) {
    constexpr int kBits = laneBits<kLanes>();
    return int32_t((unsigned(key) & ((1u << (31 - kBits)) - 1u)) << kBits | (unsigned(key) >> (31 - kBits)));
}
// A warp's scratch in the warp-per-row build: its keys as found, then in order; odd, so that the
// block's column-by-column reads of its warps' rows meet no bank conflict.
__host__ __device__ inline int buildRowStride(int space) { return 2 * space + 1; }

// Large systems (one lane a row: rows by ascending partner): a thread per row. Rows are collected in shared memory, column-major per block
// (partner c of the block's thread t at c * blockDim + t: no bank conflicts), sorted there by insertion
// (rows are short: ~75 in an LJ liquid), then written column-major to the list (consecutive threads,
// consecutive rows: coalesced).
template <class Real>
__global__ void buildListRowsKernel(NeighbourListArgs<Real> a) {
    extern __shared__ int32_t rowScratch[];
    const int64_t row = int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
    const int64_t rows = a.end - a.begin;
    if (row >= rows) return;
    int32_t* mine = rowScratch + threadIdx.x;
    const int stride = int(blockDim.x);
    const int64_t i = a.rowParticle[row];
    const Vec3<Real> xi = a.x[i];
    int32_t count = 0;
    // forEachNeighbour's walk (27 cells in ascending key, each in list order), over the cell-ordered
    // entries: a cell's particles are contiguous, so the candidates stream instead of being gathered.
    forEachNeighbourCell(a.cells.geometry, cellCoords(a.cells.geometry, xi), [&](int cell) {
        const int32_t end = a.cells.cellStart[cell + 1];
        for (int32_t k = a.cells.cellStart[cell]; k < end; ++k) {
            const CellEntry<Real> e = a.cellEntries[k];
            const Vec3<Real> d{xi.x - e.x, xi.y - e.y, xi.z - e.z};
            if (!(norm2(d) < a.reach2) || e.index == i) continue;
            if (count < a.maxNeighbours) mine[count * stride] = e.index;
            ++count;
        }
    });
    a.neighbourCount[row] = count;
    if (a.overflow && count > a.maxNeighbours) *a.overflow = 1u;
    // One atomic a warp: a million rows on one address would queue behind each other.
    const unsigned live = __activemask();
    const unsigned most = __reduce_max_sync(live, unsigned(count));
    if (int(threadIdx.x % 32) == __ffs(live) - 1) atomicMax(a.mostNeighbours, most);
    if (count > a.maxNeighbours) return;  // the list grows and is built again
    for (int32_t c = 1; c < count; ++c) {
        const int32_t key = mine[c * stride];
        int32_t k = c - 1;
        while (k >= 0 && mine[k * stride] > key) {
            mine[(k + 1) * stride] = mine[k * stride];
            --k;
        }
        mine[(k + 1) * stride] = key;
    }
    for (int32_t c = 0; c < count; ++c) a.neighbours[int64_t(c) * rows + row] = mine[c * stride];
}

// Small systems (listLanes > 1, whose rows are too few to hide a thread's walk and sort): a warp per
// row. Its lanes walk the 27 cells together (a lane a candidate, the cell-ordered entries
// read coalesced), append the partners within reach to the warp's space in shared memory (in ballot
// order) and sort them there by key (a rank sort); then the block writes its rows column by column
// (consecutive rows of a column are neighbours in memory: a warp writing its own row alone scattered
// 4-byte stores, 11 ms a step at 10^7), and each row's first lanes write where the force pass's lanes
// begin. A thread per row that sorted by insertion took 438 us for 64000 rows of an LJ liquid on an
// H200 (a fifth of the SMs' warps resident, most cycles in the sort); this kernel with a bitonic
// sort, 424 us (cell by cell) and 343 (runs of cells); `space` is at least maxNeighbours
// (buildSpaceFor).
template <class Real, int kLanes>
__global__ void buildListWarpsKernel(NeighbourListArgs<Real> a, int space) {
    extern __shared__ int32_t rowScratch[];
    __shared__ int32_t stored[32];  // each warp's row length to write (0: none)
    const int warps = int(blockDim.x / 32), warp = int(threadIdx.x / 32);
    const int64_t firstRow = int64_t(blockIdx.x) * warps;
    const int64_t row = firstRow + warp;
    const int lane = int(threadIdx.x % 32);
    const int64_t rows = a.end - a.begin;
    // A warp's scratch: the keys as found, then the keys in order; an odd stride between warps.
    const int rowStride = buildRowStride(space);
    int32_t* keys = rowScratch + size_t(warp) * size_t(rowStride);
    int32_t* ranked = keys + space;
    int32_t count = 0;
    if (row < rows) {  // the warp's lanes alike
        const int64_t i = a.rowParticle[row];
        const Vec3<Real> xi = a.x[i];
        // The 27 cells are 9 runs of the cell-ordered entries (neighbourCellRun): lane r < 9 reads run
        // r's range, a scan lays the runs end to end, and the warp takes the ~500 candidates of an LJ
        // liquid's row 32 at a time, each lane finding its run among the 9 ends it holds. Walking the
        // cells one by one took 27 dependent rounds of range and entry loads, half the lanes idle in
        // each (a cell holds ~18 particles at r_c + skin = 2.8, density 0.8): 424 us a build of
        // 64000 rows on an H200.
        const CellCoords c = cellCoords(a.cells.geometry, xi);
        int first = 0, last = 0;
        int32_t runBegin = 0, runLength = 0;
        if (lane < 9 && neighbourCellRun(a.cells.geometry, c, lane, &first, &last)) {
            runBegin = a.cells.cellStart[first];
            runLength = a.cells.cellStart[last + 1] - runBegin;
        }
        int32_t runEnd = runLength;  // inclusive scan: where run `lane` ends in the laid-out candidates
        for (int offset = 1; offset < 16; offset *= 2) {
            const int32_t before = __shfl_up_sync(0xffffffffu, runEnd, offset);
            if (lane >= offset) runEnd += before;
        }
        int32_t ends[9];
#pragma unroll
        for (int r = 0; r < 9; ++r) ends[r] = __shfl_sync(0xffffffffu, runEnd, r);
        const int32_t shift = runBegin - (runEnd - runLength);  // candidate t of run `lane` is entry t + shift
        const int32_t total = ends[8];
        for (int32_t t0 = 0; t0 < total; t0 += 32) {
            const int32_t t = t0 + lane;
            int run = 0;
#pragma unroll
            for (int r = 0; r < 8; ++r) run += t >= ends[r] ? 1 : 0;
            const int32_t k = t + __shfl_sync(0xffffffffu, shift, run);
            bool near = false;
            int32_t j = 0;
            if (t < total) {
                const CellEntry<Real> e = a.cellEntries[k];
                const Vec3<Real> d{xi.x - e.x, xi.y - e.y, xi.z - e.z};
                j = e.index;
                near = norm2(d) < a.reach2 && e.index != i;
            }
            const unsigned taken = __ballot_sync(0xffffffffu, near);
            const int32_t slot = count + __popc(taken & ((1u << lane) - 1u));
            if (near && slot < space) keys[slot] = laneKey<kLanes>(j);
            count += __popc(taken);
        }
        if (lane == 0) {
            a.neighbourCount[row] = count;
            // An atomic only above the largest seen so far: 10^6 rows on one address would queue.
            if (unsigned(count) > *static_cast<volatile unsigned*>(a.mostNeighbours)) atomicMax(a.mostNeighbours, unsigned(count));
            if (a.overflow && count > a.maxNeighbours) *a.overflow = 1u;
        }
    }
    const bool store = row < rows && count <= a.maxNeighbours;  // else the list grows and is built again
    if (store) {
        // Rank sort: a key's place is the number of smaller keys (the keys are distinct partners).
        // Each lane takes four keys and counts them against the row's keys, which the lanes read in
        // step (broadcasts): a load and eight instructions for four comparisons. The bitonic network
        // this replaces spent most of the build's 340 us (64000 rows, H200) in 28 passes over 128 keys.
        __syncwarp();
        for (int32_t base = 0; base < count; base += 128) {
            int32_t mine[4], rank[4];
#pragma unroll
            for (int u = 0; u < 4; ++u) {
                const int32_t c = base + 32 * u + lane;
                mine[u] = c < count ? keys[c] : INT32_MAX;
                rank[u] = 0;
            }
            for (int32_t m = 0; m < count; ++m) {
                const int32_t key = keys[m];
#pragma unroll
                for (int u = 0; u < 4; ++u) rank[u] += key < mine[u] ? 1 : 0;
            }
#pragma unroll
            for (int u = 0; u < 4; ++u)
                if (base + 32 * u + lane < count) ranked[rank[u]] = partnerOfKey<kLanes>(mine[u]);
        }
        __syncwarp();
        if (lane < kLanes) {  // lane t's partners begin at the first of residue t
            int32_t lo = 0, hi = count;
            while (lo < hi) {
                const int32_t mid = (lo + hi) / 2;
                if (int(unsigned(ranked[mid]) % unsigned(kLanes)) < lane) lo = mid + 1;
                else hi = mid;
            }
            a.laneStart[int64_t(lane) * rows + row] = lo;
        }
    }
    if (lane == 0) stored[warp] = store ? count : 0;
    __syncthreads();
    for (int32_t k = int32_t(threadIdx.x); k < warps * space; k += int32_t(blockDim.x)) {  // rowStride odd: no bank conflicts
        const int w = k % warps;
        const int32_t c = k / warps;
        if (c < stored[w]) a.neighbours[int64_t(c) * rows + firstRow + w] = rowScratch[size_t(w) * size_t(rowStride) + size_t(space + c)];
    }
}

template <class Real>
__global__ void gatherCellEntriesKernel(const Vec3<Real>* x, const int32_t* sorted, int64_t n, CellEntry<Real>* entries) {
    const int64_t k = int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
    if (k >= n) return;
    const int32_t j = sorted[k];
    const Vec3<Real> p = x[j];
    entries[k] = CellEntry<Real>{p.x, p.y, p.z, j};
}

// How many rows of `bytesPerRow` shared bytes a block of the list build holds beside `reserved` bytes,
// at most `most`; a row that does not fit at all is refused with the remedy.
inline int rowsThatFit(int32_t partners, int64_t bytesPerRow, int64_t reserved, int most) {
    int device = 0, optIn = 0;
    cudaGetDevice(&device);
    cudaDeviceGetAttribute(&optIn, cudaDevAttrMaxSharedMemoryPerBlockOptin, device);
    const int64_t fit = bytesPerRow > 0 ? (int64_t(optIn) - reserved) / bytesPerRow : most;
    if (fit < 1)
        throw DeviceError("neighbour list: a row of " + std::to_string(partners) +
                          " partners does not fit a block's shared memory; the cutoff plus skin spans too many particles for lists "
                          "(use forces = \"all_pairs\")");
    return int(fit < most ? fit : most);
}

// Threads per block of the thread-per-row build: 64, or 32, or as many as fit.
inline int buildBlockFor(int32_t maxNeighbours) {
    const int fit = rowsThatFit(maxNeighbours, int64_t(maxNeighbours) * int64_t(sizeof(int32_t)), 0, 64);
    return fit == 64 ? 64 : fit >= 32 ? 32 : fit;
}

// The build's shared space per row for its keys: maxNeighbours (at least a warp's width).
inline int buildSpaceFor(int32_t maxNeighbours) { return maxNeighbours > 32 ? int(maxNeighbours) : 32; }

// Warps per block of the warp-per-row build: 8, fewer where their rows do not fit (1 KB kept for the
// static counts and the driver). A block ends with its slowest row: 32 rows a block took 208 us for
// 64000 rows of an LJ liquid on an H200, 8 took 188.
inline int buildWarpsFor(int space) { return rowsThatFit(space, int64_t(buildRowStride(space)) * int64_t(sizeof(int32_t)), 1024, 8); }

template <class Real>
__global__ void listMovedKernel(const Vec3<Real>* x, const Vec3<Real>* xBuilt, int64_t begin, int64_t end, Real halfSkin2,
                                unsigned int* moved) {
    const int64_t row = int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
    if (row >= end - begin) return;
    const Real d2 = norm2(x[begin + row] - xBuilt[row]);
    if (!(d2 <= halfSkin2)) *moved = 1u;  // NaN included
}

// The screen words of one row (ForceArgs::screen), reduced over the warp's live rows first so that a
// pass of 10^6 rows makes tens of thousands of atomics, not millions. Rounded so that the screen
// never reports a pair farther or a wall nearer than they are.
template <class Real>
__device__ void screenRow(const ForceArgs<Real>& a, Vec3<Real> xi, Real ai, Real nearest) {
    const Real depth = deepestWallApproach(xi, screenReach(ai, a.contactGap), a.box);
    const bool finite = isfinite(xi.x) && isfinite(xi.y) && isfinite(xi.z);
    const float nearestF = sizeof(Real) == sizeof(float) ? float(nearest) : __double2float_rd(double(nearest));
    const float depthF = sizeof(Real) == sizeof(float) ? float(depth) : __double2float_ru(double(depth));
    const unsigned live = __activemask();
    // Non-negative floats order as their bits do.
    const unsigned nearestBits = __reduce_min_sync(live, nearestF >= 0.0f ? __float_as_uint(nearestF) : 0u);
    const unsigned depthBits = __reduce_max_sync(live, depthF > 0.0f ? __float_as_uint(depthF) : 0u);
    const bool anyNonFinite = __any_sync(live, !finite || !(nearest >= Real(0)));
    if (int(threadIdx.x % 32) == __ffs(live) - 1) {
        atomicMin(&a.screen[0], nearestBits);
        if (depthBits != 0u) atomicMax(&a.screen[1], depthBits);
        if (anyNonFinite) a.screen[2] = 1u;
    }
}

// kLanes consecutive threads per row (listLanes): lane t sums the partners j with j % kLanes == t,
// which the build put together in ascending j (ForceArgs::laneStart), and the lanes' sums are added
// in a fixed tree (shuffles down by kLanes / 2, ..., 1). Which lane takes a pair depends on the partner
// alone, not on its place in the row, so a row's sum does not depend on when the list was built (the
// pairs listed beyond the cutoff add exact zeros to their lanes): restarts stay bit-identical, and
// every run and every pass over lists of these particles gives the same bits. Small systems have too
// few rows to hide the latency of a row's serial walk (an LJ liquid of 4000 on an H200: 35 us a pass
// with a thread per row, 12 with eight); large ones have rows enough. Tried: lanes striding the row by
// place (0.032 against 0.046 ms a pass at 64000, but the sum then depends on the list's extra pairs:
// restarts broke); lanes skipping the others' partners (divergent, slower); lanes striding by place
// with the terms added in list order by shuffles (the one-thread bits for any lane count, but the
// serial shuffles cost more than the imbalance: 0.051 ms fp32, 0.080 fp64 at 64000).
// With rowIndex (one GPU, whose lists have a row per particle) row k is particle rowIndex[begin + k]'s,
// whose acceleration goes there: the collision stage's end-of-step accelerations of the particles
// it resolves.
// Row `row` of the lists, particle i's, into acceleration[out]; its kLanes lanes call this together
// (the shuffles see the whole group).
template <class Real, bool kEnergy, bool kSingleSpecies, int kLanes>
__device__ __forceinline__ void listForceRow(const ForceArgs<Real>& a, int64_t i, int64_t row, int64_t out, int lane) {
    const int64_t rows = a.listRows;
    const Vec3<Real> xi = a.x[i];
    const int si = a.species[i];
    const int s = a.table.count;
    const PairCoefficients<Real> single = a.table.pairs[0];
    const int32_t count = a.neighbourCount[row];
    // The collision screen (ForceArgs::screen): each pair's reach is its contact distance plus the gap, with a margin.
    const bool screen = a.screen != nullptr;
    const Real ai = screen ? a.table.radius[si] : Real(0);
    const Real singleReach = screenReach(ai + ai, a.contactGap);
    const Real singleInverse = screen ? Real(1) / (singleReach * singleReach) : Real(0);
    Real nearest = Real(INFINITY);  // smallest R^2 / reach^2 of the row
    Vec3<Real> force{0, 0, 0};
    double energy = 0;
    const int32_t first = kLanes > 1 ? a.laneStart[int64_t(lane) * rows + row] : 0;
    const int32_t last = kLanes > 1 && lane + 1 < kLanes ? a.laneStart[int64_t(lane + 1) * rows + row] : count;
    auto add = [&](int32_t j, const Vec3<Real>& xj) {
        const Vec3<Real> d = xi - xj;
        const int sj = kSingleSpecies ? 0 : a.species[j];
        const PairCoefficients<Real>& p = kSingleSpecies ? single : a.table.pairs[si * s + sj];
        Real u = 0;
        const Real r2 = norm2(d);
        const Real f = pairForceOverR(p, r2, kEnergy ? &u : nullptr);
        force += f * d;
        if (kEnergy) energy += double(u);
        if (screen) {
            Real inverse = singleInverse;
            if (!kSingleSpecies) {
                const Real reach = screenReach(ai + a.table.radius[sj], a.contactGap);
                inverse = Real(1) / (reach * reach);
            }
            nearest = fmin(nearest, r2 * inverse);
        }
    };
    // Partners in batches of four: their indices, then their positions, are loaded before any is used,
    // so a lane has four gathers in flight instead of one (the terms still add in list order).
    int32_t c = first;
    for (; c + 4 <= last; c += 4) {
        int32_t j[4];
        Vec3<Real> xj[4];
#pragma unroll
        for (int u = 0; u < 4; ++u) j[u] = a.neighbours[int64_t(c + u) * rows + row];
#pragma unroll
        for (int u = 0; u < 4; ++u) xj[u] = a.x[j[u]];
#pragma unroll
        for (int u = 0; u < 4; ++u) add(j[u], xj[u]);
    }
    for (; c < last; ++c) {
        const int32_t j = a.neighbours[int64_t(c) * rows + row];
        add(j, a.x[j]);
    }
    if (kLanes > 1) {
        const unsigned group = (kLanes == 32 ? 0xffffffffu : ((1u << kLanes) - 1u)) << (threadIdx.x % 32 / kLanes * kLanes);
        for (int offset = kLanes / 2; offset > 0; offset /= 2) {
            force.x += __shfl_down_sync(group, force.x, offset, kLanes);
            force.y += __shfl_down_sync(group, force.y, offset, kLanes);
            force.z += __shfl_down_sync(group, force.z, offset, kLanes);
            if (kEnergy) energy += __shfl_down_sync(group, energy, offset, kLanes);
            if (screen) nearest = fmin(nearest, __shfl_down_sync(group, nearest, offset, kLanes));
        }
        if (lane != 0) return;
    }
    const Vec3<Real> acceleration = a.table.invMass[si] * force + a.table.field[si];
    a.acceleration[out] = acceleration;
    if (a.kickV) {
        Vec3<Real> v = a.kickV[out];
        verletKick(v, acceleration, a.kickH);
        a.kickV[out] = v;
    }
    if (kEnergy) a.pairEnergy[out] = energy;
    if (screen) screenRow(a, xi, ai, nearest);
    if (a.forecast.moves) forecastParticle(a.forecast, out, xi, a.forecast.v[out], acceleration);
}

template <class Real, bool kEnergy, bool kSingleSpecies, int kLanes>
__global__ void listForceKernel(ForceArgs<Real> a) {
    const int64_t k = (int64_t(blockIdx.x) * blockDim.x + threadIdx.x) / kLanes;
    const int lane = int(threadIdx.x % kLanes);
    // A row's lanes live or leave together (same k).
    if (k >= a.end - a.begin || !gateOpen(a.gate)) return;
    if (a.rowMask && !a.rowIndex && !a.rowMask[k]) return;  // a coalesced byte per row, nothing else read
    const int64_t i = a.rowIndex ? int64_t(a.rowIndex[a.begin + k]) : int64_t(a.rowParticle[k]);
    const int64_t row = a.rowIndex ? int64_t(a.rowOf[i]) : k;
    listForceRow<Real, kEnergy, kSingleSpecies, kLanes>(a, i, row, a.rowIndex ? i : i - a.begin, lane);
}

// launchStageSumsAndRefresh: the first sumRows x sums.blocks blocks sum, the others refresh. Item k of
// moved x (columns + 1) is moved particle k / (columns + 1)'s own row (slot 0) or its partner's in
// column slot - 1. A row two moved particles share is summed twice, to the same bits: nothing it reads
// changes during the launch.
template <class Real, int kLanes>
__global__ void stageSumsAndRefreshKernel(BlockSumArgs sums, int sumRows, ForceArgs<Real> a, const int32_t* moved,
                                          const unsigned int* movedCount, int32_t columns) {
    const int sumBlocks = sums.blocks * sumRows;
    if (int(blockIdx.x) < sumBlocks) {
        blockSum(sums, int(blockIdx.x) % sums.blocks, int(blockIdx.x) / sums.blocks);
        return;
    }
    if (!gateOpen(a.gate)) return;
    const int lane = int(threadIdx.x % kLanes);
    const int64_t block = int64_t(blockIdx.x) - sumBlocks;
    const int64_t groups = (int64_t(gridDim.x) - sumBlocks) * blockDim.x / kLanes, slots = int64_t(columns) + 1;
    const int64_t items = int64_t(*movedCount) * slots;
    for (int64_t k = (block * blockDim.x + threadIdx.x) / kLanes; k < items; k += groups) {  // a group's lanes alike
        const int64_t p = moved[k / slots], slot = k % slots;
        int64_t i = p;
        if (slot > 0) {
            const int64_t row = a.rowOf[p];
            if (slot > a.neighbourCount[row]) continue;
            i = a.neighbours[(slot - 1) * a.listRows + row];
        }
        if (a.table.count == 1) listForceRow<Real, false, true, kLanes>(a, i, a.rowOf[i], i, lane);
        else listForceRow<Real, false, false, kLanes>(a, i, a.rowOf[i], i, lane);
    }
}

template <class Real>
__global__ void listVirialKernel(ForceArgs<Real> a, double* out) {
    const int64_t row = int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
    const int64_t rows = a.listRows;
    if (row >= a.end - a.begin) return;
    const int64_t i = a.rowParticle[row];
    const Vec3<Real> xi = a.x[i];
    const PairCoefficients<Real>* pairs = a.table.pairs + a.species[i] * a.table.count;
    const int32_t count = a.neighbourCount[row];
    double w = 0;
    for (int32_t c = 0; c < count; ++c) {
        const int32_t j = a.neighbours[int64_t(c) * rows + row];
        const Real r2 = norm2(xi - a.x[j]);
        w += double(pairForceOverR(pairs[a.species[j]], r2, static_cast<Real*>(nullptr))) * double(r2);
    }
    out[i - a.begin] = 0.5 * w;  // by particle: summed in particle order, whatever the rows' order
}

__global__ void rowOrderKernel(const int32_t* sorted, int64_t n, int64_t begin, int64_t end, int32_t* rowParticle, int32_t* rowOf) {
    const int64_t row = int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
    if (row >= end - begin) return;
    const int32_t p = (begin == 0 && end == n) ? sorted[row] : int32_t(begin + row);
    rowParticle[row] = p;
    rowOf[p - begin] = int32_t(row);
}

// A warp takes 32 particles and walks the rows of each moved one together (a lane a partner): a
// thread walking a row alone waited on its partners one after another (a few hundred wall hits in an
// LJ fluid of 64000: 26 us a pass on an H200).
template <class Real>
__global__ void touchMovedKernel(const Vec3<Real>* x, const Vec3<Real>* xBefore, const char* moved, int64_t rows, const int32_t* rowOf,
                                 const int32_t* neighbours, const int32_t* neighbourCount, unsigned char* touched) {
    const int64_t p = int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
    const int lane = int(threadIdx.x % 32);
    bool mine = p < rows;
    if (mine) {
        if (moved) {
            mine = moved[p] != 0;
        } else {
            const Vec3<Real> a = x[p], b = xBefore[p];
            mine = !(a.x == b.x && a.y == b.y && a.z == b.z);
        }
    }
    for (unsigned pending = __ballot_sync(0xffffffffu, mine); pending != 0; pending &= pending - 1) {
        const int64_t q = p - lane + (__ffs(pending) - 1);
        const int64_t row = rowOf[q];
        if (lane == 0) touched[row] = 1;
        const int32_t count = neighbourCount[row];
        for (int32_t c = lane; c < count; c += 32) touched[rowOf[neighbours[int64_t(c) * rows + row]]] = 1;  // every writer writes 1
    }
}

}  // namespace

template <class Real>
void launchListVirialRows(const ForceArgs<Real>& a, double* row, cudaStream_t stream) {
    const int64_t rows = a.end - a.begin;
    if (rows <= 0) return;
    listVirialKernel<Real><<<blocksFor(rows), kBlock, 0, stream>>>(a, row);
    checkLaunch("list virial kernel");
}

void launchListRowOrder(const CellListView& cells, int64_t n, int64_t begin, int64_t end, int32_t* rowParticle, int32_t* rowOf,
                        cudaStream_t stream) {
    if (end <= begin) return;
    rowOrderKernel<<<blocksFor(end - begin), kBlock, 0, stream>>>(cells.sorted, n, begin, end, rowParticle, rowOf);
    checkLaunch("list row order kernel");
}

template <class Real>
void launchTouchMoved(const Vec3<Real>* x, const Vec3<Real>* xBefore, const char* moved, int64_t rows, const int32_t* rowOf,
                      const int32_t* neighbours, const int32_t* neighbourCount, unsigned char* touched, cudaStream_t stream) {
    if (rows <= 0) return;
    cudaMemsetAsync(touched, 0, size_t(rows), stream);
    touchMovedKernel<Real><<<blocksFor(rows), kBlock, 0, stream>>>(x, xBefore, moved, rows, rowOf, neighbours, neighbourCount, touched);
    checkLaunch("touched rows kernel");
}

template <class Real>
void launchBuildNeighbourList(const NeighbourListArgs<Real>& a, cudaStream_t stream) {
    const int64_t rows = a.end - a.begin;
    cudaMemsetAsync(a.mostNeighbours, 0, sizeof(unsigned int), stream);
    if (rows <= 0) return;
    if (a.lanes == 1) {
        const int block = buildBlockFor(a.maxNeighbours);
        const size_t shared = size_t(block) * size_t(a.maxNeighbours) * sizeof(int32_t);
        cudaFuncSetAttribute(buildListRowsKernel<Real>, cudaFuncAttributeMaxDynamicSharedMemorySize, int(shared));
        buildListRowsKernel<Real><<<blocksFor(rows, block), unsigned(block), shared, stream>>>(a);
    } else {
        const int space = buildSpaceFor(a.maxNeighbours);
        const int warps = buildWarpsFor(space);
        const size_t shared = size_t(warps) * size_t(buildRowStride(space)) * sizeof(int32_t);
        auto kernel = a.lanes == 8 ? buildListWarpsKernel<Real, 8> : buildListWarpsKernel<Real, 4>;
        if (a.lanes != 8 && a.lanes != 4) throw DeviceError("neighbour list: the warp build takes 4 or 8 lanes");
        if (shared > 32 * 1024) cudaFuncSetAttribute(kernel, cudaFuncAttributeMaxDynamicSharedMemorySize, int(shared));
        kernel<<<blocksFor(rows, warps), unsigned(32 * warps), shared, stream>>>(a, space);
    }
    checkLaunch("neighbour list kernel");
}

template <class Real>
void launchListMoved(const Vec3<Real>* x, const Vec3<Real>* xBuilt, int64_t begin, int64_t end, Real halfSkin2, unsigned int* moved,
                     cudaStream_t stream) {
    cudaMemsetAsync(moved, 0, sizeof(unsigned int), stream);
    if (end <= begin) return;
    listMovedKernel<Real><<<blocksFor(end - begin), kBlock, 0, stream>>>(x, xBuilt, begin, end, halfSkin2, moved);
    checkLaunch("list displacement kernel");
}

template <class Real, int kLanes>
void launchListForcesWith(const ForceArgs<Real>& a, cudaStream_t stream) {
    const int64_t rows = a.end - a.begin;
    const bool single = a.table.count == 1;
    const unsigned blocks = blocksFor(rows * kLanes);
    if (a.pairEnergy) {
        if (single) listForceKernel<Real, true, true, kLanes><<<blocks, kBlock, 0, stream>>>(a);
        else listForceKernel<Real, true, false, kLanes><<<blocks, kBlock, 0, stream>>>(a);
    } else {
        if (single) listForceKernel<Real, false, true, kLanes><<<blocks, kBlock, 0, stream>>>(a);
        else listForceKernel<Real, false, false, kLanes><<<blocks, kBlock, 0, stream>>>(a);
    }
    checkLaunch("neighbour list force kernel");
}

// A grid for work the device counts (a stage's few hundred rows): two blocks a multiprocessor,
// whatever the count (none: every block leaves at once).
inline unsigned countedGridBlocks() { return unsigned(2 * multiprocessorCount()); }

template <class Real>
void launchStageSumsAndRefresh(const BlockSumArgs& sums, int rows, const ForceArgs<Real>& a, const int32_t* moved,
                               const unsigned int* movedCount, int32_t columns, cudaStream_t stream) {
    static_assert(kReduceBlock == kBlock, "the sums' blocks and the refresh's are one launch's");
    const unsigned blocks = unsigned(sums.blocks * rows) + countedGridBlocks();
    switch (listLanes(a.n)) {
        case 8: stageSumsAndRefreshKernel<Real, 8><<<blocks, kBlock, 0, stream>>>(sums, rows, a, moved, movedCount, columns); break;
        case 4: stageSumsAndRefreshKernel<Real, 4><<<blocks, kBlock, 0, stream>>>(sums, rows, a, moved, movedCount, columns); break;
        default: stageSumsAndRefreshKernel<Real, 1><<<blocks, kBlock, 0, stream>>>(sums, rows, a, moved, movedCount, columns); break;
    }
    checkLaunch("stage sums and refresh kernel");
}

// Called by launchForces (force_kernels.cu) when the args carry a list.
template <class Real>
void launchListForces(const ForceArgs<Real>& a, cudaStream_t stream) {
    if (a.end - a.begin <= 0) return;
    switch (listLanes(a.n)) {
        case 8: launchListForcesWith<Real, 8>(a, stream); break;
        case 4: launchListForcesWith<Real, 4>(a, stream); break;
        default: launchListForcesWith<Real, 1>(a, stream); break;
    }
}

template <class Real>
void launchGatherCellEntries(const Vec3<Real>* x, const int32_t* sorted, int64_t n, CellEntry<Real>* entries, cudaStream_t stream) {
    if (n <= 0) return;
    gatherCellEntriesKernel<Real><<<blocksFor(n), kBlock, 0, stream>>>(x, sorted, n, entries);
    checkLaunch("cell entries kernel");
}

template void launchGatherCellEntries<float>(const Vec3<float>*, const int32_t*, int64_t, CellEntry<float>*, cudaStream_t);
template void launchGatherCellEntries<double>(const Vec3<double>*, const int32_t*, int64_t, CellEntry<double>*, cudaStream_t);
template void launchBuildNeighbourList<float>(const NeighbourListArgs<float>&, cudaStream_t);
template void launchBuildNeighbourList<double>(const NeighbourListArgs<double>&, cudaStream_t);
template void launchListVirialRows<float>(const ForceArgs<float>&, double*, cudaStream_t);
template void launchListVirialRows<double>(const ForceArgs<double>&, double*, cudaStream_t);
template void launchTouchMoved<float>(const Vec3<float>*, const Vec3<float>*, const char*, int64_t, const int32_t*, const int32_t*,
                                      const int32_t*, unsigned char*, cudaStream_t);
template void launchTouchMoved<double>(const Vec3<double>*, const Vec3<double>*, const char*, int64_t, const int32_t*, const int32_t*,
                                       const int32_t*, unsigned char*, cudaStream_t);
template void launchListMoved<float>(const Vec3<float>*, const Vec3<float>*, int64_t, int64_t, float, unsigned int*, cudaStream_t);
template void launchListMoved<double>(const Vec3<double>*, const Vec3<double>*, int64_t, int64_t, double, unsigned int*, cudaStream_t);
template void launchStageSumsAndRefresh<float>(const BlockSumArgs&, int, const ForceArgs<float>&, const int32_t*, const unsigned int*, int32_t,
                                               cudaStream_t);
template void launchStageSumsAndRefresh<double>(const BlockSumArgs&, int, const ForceArgs<double>&, const int32_t*, const unsigned int*, int32_t,
                                                cudaStream_t);
template void launchListForces<float>(const ForceArgs<float>&, cudaStream_t);
template void launchListForces<double>(const ForceArgs<double>&, cudaStream_t);

}  // namespace corebox::gpu
