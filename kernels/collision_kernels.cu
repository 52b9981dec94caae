// A posteriori collision rounds on the GPU (DESIGN.md sec. 2) with the shared event and resolution
// functions of collision_resolution.h. Contacts are found through the cell list (cell_list.h, cells at
// least the largest contact distance of the particles in them wide, a few large ones walked apart),
// rebuilt by cell_list_kernels.cu where a round's resolution moved a particle out of its cell, or
// through candidate rows (impact_candidates.cuh, a Verlet list of the rounds) where the rounds have them.
// Tried and not kept: the search reading its partners from a copy of the state gathered in the grid's
// order each round (position with radius, velocity with the active flag, side by side; a row of cells
// one contiguous range), the partner's index read only for an event. The same bits, no gain: an H200,
// fp32, one call, `corebox bench pile` 10^6 balls 61.3 ms a frame against 58.8 (the last second 41.5
// against 41.1), 10^5 14.4 against 14.5; the sandbox at 10^5 balls 14.3 and 14.0 against 14.4 and 14.5.
// The threads already take particles in the grid's order, so a warp's partners are in L1; the gather
// cost what the reads saved.
// Tried and not kept: the rounds' kernels (searches, collection, resolution) launched with programmatic
// dependent launch (griddepcontrol: each scheduled behind the last blocks of the kernel before and waiting
// for it inside): the 1.3 to 1.6 us the GPU stood idle between them went (CUPTI), but the kernels' times
// grew by as much (the scattered search 46 us a round against 34, the collection 14.2 against 8.9), and
// `corebox bench pile` 10^6 balls took 32.82 and 32.82 ms a frame against 32.95 and 32.78 (an H200, fp32,
// separate binaries in one call): the idle time moved into the kernels rather than going.
#include <algorithm>

#include "gpu_common.cuh"
#include "gpu_launch.h"
#include "impact_candidates.cuh"
#include "neighbour_walk.cuh"
#include "step_check.cuh"

namespace corebox::gpu {
namespace {

template <class Real>
__global__ void openStageKernel(StageOpenArgs<Real> a) {
    const int64_t i = int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
    if (i < 3) a.kindCounts[i] = 0;
    if (i < a.zeroCount) a.zero[i] = 0;
    if (i >= a.n) return;
    if (a.active) a.active[i] = startsActive(a.v[i], a.restingSpeed) ? 1 : 0;
    if (a.events) a.events[i] = noEvent();
    if (!a.flagged[i]) return;
    for (int r = 0; r < a.rowCount; ++r) a.rows[size_t(r) * size_t(a.n) + size_t(i)] = 0;
    a.flagged[i] = 0;
}

// Whether this round's search is narrowed to the marked particles (CollisionArgs::walker): where the
// round before left fewer than one particle in kNarrowedActiveShare active. With more, nearly every
// particle is near an active one and the marks cost more than they save.
constexpr int64_t kNarrowedActiveShare = 8;
template <class Real>
__device__ bool narrowed(const CollisionArgs<Real>& a) {
    return int64_t(*a.activeInCount) * kNarrowedActiveShare < a.p.n;
}

// Whether the round before's list of active particles (CollisionArgs::activeIn) is short enough for the
// listed scattered search (scatterListedEventsKernel) instead of a thread a particle.
template <class Real>
__device__ inline bool listedScatter(const CollisionArgs<Real>& a) {
    if (!a.activeIn || a.listedScatterMax <= 0) return false;
    const int64_t count = int64_t(*a.activeInCount);
    return count <= a.listedScatterMax && count * kListedScatterShare <= a.p.n;
}

// Particle i's earliest event of the round: kept, counted, listed for the next round, and listed for an
// end-of-step acceleration where it has none yet.
template <class Real>
__device__ void recordEvent(const CollisionArgs<Real>& a, int64_t i, const CollisionEvent& best) {
    a.events[i] = best;
    if (!isValid(best)) return;
    const unsigned listed = warpAggregatedIncrement(&a.counters[1]);  // a count: the same whatever the order
    if (a.activeOut) a.activeOut[listed] = int32_t(i);                // the next round's searches start from these
    if (!a.hasContactAcceleration[i]) {
        const unsigned slot = warpAggregatedIncrement(&a.counters[0]);  // list order varies, each entry's work does not
        a.needList[slot] = int32_t(i);
        a.hasContactAcceleration[i] = 1;
    }
}

// The earliest of the events the G lanes of a group (mask) found, in every lane: a total order, so the
// same whatever lane found which.
template <int G>
__device__ inline CollisionEvent groupBest(CollisionEvent best, unsigned mask) {
    for (int offset = G / 2; offset > 0; offset /= 2) {
        const CollisionEvent other{__shfl_xor_sync(mask, best.key, offset),
                                   int64_t(__shfl_xor_sync(mask, (long long)best.partner, offset))};
        if (isBetter(other, best)) best = other;
    }
    return best;
}

// G lanes a particle (neighbour_walk.cuh; G = 1: a thread walks alone), whole groups in a block.
template <class Real, int G>
__global__ void findEventsKernel(CollisionArgs<Real> a) {
    waitForPrimary();
    const int64_t t = int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
    const int64_t k = t / G;
    const int rank = int(t % G);
    if (k >= a.p.n || (a.gate && *a.gate == 0u) || listedScatter(a)) return;  // the whole group
    // Threads take particles in the cell list's order: a warp's 27-cell walks overlap, so its loads of
    // the partners hit the caches (in index order, 10^7 particles took 14 ms per search on an H200).
    const int64_t i = a.grid.sorted[k];
    if (a.walker && narrowed(a)) {  // a later round: only the particles near an active one (launchMarkSearchers)
        const bool marked = a.walker[i] != 0;
        if (G > 1) __syncwarp(groupMask<G>());  // every lane has read the mark before it is cleared
        if (!marked) return;  // the whole group
        if (rank == 0) a.walker[i] = 0;
    }
    const bool checkAll = a.active[i] != 0;
    const Vec3<Real> xi = a.p.x[i], vi = a.p.v[i];
    const Real ri = a.table.radius[a.p.species[i]];
    CollisionEvent best = noEvent();
    auto consider = [&](int64_t j) {
        if (j == i || !(checkAll || a.active[j])) return;
        considerPair(xi, vi, ri, a.p.x[j], a.p.v[j], a.table.radius[a.p.species[j]], j, a.window, best);
    };
    if (G == 1) {
        forEachCandidate(a.grid, a.candidates, i, xi, ri, consider);
    } else {
        forEachCandidateShared<G>(a.grid, a.candidates, i, xi, ri, rank, consider);
        best = groupBest<G>(best, groupMask<G>());
        if (rank != 0) return;
    }
    considerWalls(xi, vi, ri, a.box, a.window, best);
    recordEvent(a, i, best);
}

// A thread an active particle of the round before: every particle in the cells around it may find an
// event with it. Inactive particles meet only active ones (resolveKernel: inactive = no event in the
// round before, and not moved since), so the rest keep their no-event; the marks are a superset, never
// a different result. The grid covers n (the count is on the device).
template <class Real>
__global__ void markSearchersKernel(CollisionArgs<Real> a) {
    const int64_t t = int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
    if ((a.gate && *a.gate == 0u) || !narrowed(a) || t >= int64_t(*a.activeInCount)) return;
    const int64_t i = a.activeIn[t];
    forEachCandidate(a.grid, a.candidates, i, a.p.x[i], a.table.radius[a.p.species[i]],
                     [&](int64_t j) { a.walker[j] = 1; });
}

// The scattered search (launchScatteredSearch). An fp32 pair event as one word that orders as isBetter
// orders events: the key (a rewind time >= 0, whose bits order as its value; a zero's sign dropped,
// isBetter does not see it) above, the partner below, complemented so that the lower partner is the
// larger word; 0 is no event.
__device__ inline unsigned long long packedEvent(float key, int64_t partner) {
    return (static_cast<unsigned long long>(__float_as_uint(key + 0.0f)) << 32) |
           (0xFFFFFFFFull - static_cast<unsigned long long>(partner + 1));
}

__device__ inline CollisionEvent unpackedEvent(unsigned long long word) {
    const float key = __uint_as_float(static_cast<unsigned>(word >> 32));
    return CollisionEvent{double(key), int64_t(0xFFFFFFFFull - (word & 0xFFFFFFFFull)) - 1};
}

// The scattered searches' pair (i, j), i active: the pair's impact joins i's best event, and is offered
// to j's word where j is inactive (atomicMax: the same earliest whatever the order).
__device__ inline void offerPair(const CollisionArgs<float>& a, unsigned long long* offered, int64_t i, Vec3<float> xi,
                                 Vec3<float> vi, float ri, int64_t j, CollisionEvent& best) {
    if (j == i) return;
    const float s = pairImpactRewind(xi, vi, ri, a.p.x[j], a.p.v[j], a.table.radius[a.p.species[j]], a.window);
    if (!(s >= 0.0f)) return;
    const CollisionEvent e{double(s), j};
    if (isBetter(e, best)) best = e;
    if (!a.active[j]) atomicMax(&offered[j], packedEvent(s, i));
}

// Each active particle (with an event in the round before; in a stage's first round, fast enough for an
// impact): its earliest event among every neighbour and the walls, as findEventsKernel finds it, and for
// each inactive neighbour it overlaps in an impact, the pair's event offered to that neighbour's word
// (atomicMax: the same earliest whatever the order). An inactive particle meets only active ones, and the pair's key is
// the same bits from either side (pairImpactRewind), so the words hold what the inactive particles' own searches would
// find; they walk no cells. Threads take the particles in the cell list's order, as findEventsKernel does: a warp's
// walks overlap in the caches, and a warp of inactive particles ends at once (from the last round's list
// of active particles instead, a thread each, the sandbox example at 10^5 balls took 14 ms a frame against
// 12; a warp each where the list is short: scatterListedEventsKernel). Tried and not kept either: from that
// list, a thread each, only where it was short (fewer than one particle in 32), and the offers
// collected from a list of the particles offered one (each listed by the offer that found its word empty,
// an atomic on one count each) by a grid that fits at once, instead of a thread a particle: the same bits,
// but `corebox bench pile` 10^6 balls took 38.9 and 38.7 ms a frame against 37.0 and 37.2, and the
// phi = 0.45 fluid at 10^6 641 steps/s against 664 (an H200, fp32, separate binaries in one call).
__global__ void scatterEventsKernel(CollisionArgs<float> a, unsigned long long* offered) {
    const int64_t k = int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
    if (k >= a.p.n || (a.gate && *a.gate == 0u) || listedScatter(a)) return;
    const int64_t i = a.grid.sorted[k];
    if (!a.active[i]) return;
    const Vec3<float> xi = a.p.x[i], vi = a.p.v[i];
    const float ri = a.table.radius[a.p.species[i]];
    CollisionEvent best = noEvent();
    forEachCandidate(a.grid, a.candidates, i, xi, ri,
                     [&](int64_t j) { offerPair(a, offered, i, xi, vi, ri, j, best); });
    considerWalls(xi, vi, ri, a.box, a.window, best);
    recordEvent(a, i, best);
}

// The scattered search from the round before's list of active particles, kListedScatterLanes lanes a
// particle (neighbour_walk.cuh: the cells' bounds loaded at once, the candidates shared out): a sparse
// round's active particles are one to a warp of scatterEventsKernel, whose round then lasts one thread's
// walk, 27 cells and their candidates one dependent load after another. The same events and offers (the
// earliest by a total order, offers by atomicMax), so the same bits. A grid that fits at once strides the
// list (its length is on the device). An H200, fp32, separate runs in one call, with and without: the
// sandbox example at 10^5 balls (whose rounds every particle searches: launchSparseOrFullSearch) 3.69
// and 3.72 ms a frame in its impacts against 3.86 and 3.79, the same state hash; `corebox bench pile`
// 10^6 balls 36.65 and 36.76 ms a frame against 36.84 and 36.74 (its landing's scattered searches 645 ms
// against 683 over the 5 s, CUPTI: most of its rounds have more active particles than the list takes).
// Lists of up to 131,072 particles: 37.96, slower (a warp a particle is too many warps for them).
// Tried and not kept: this kernel and scatterEventsKernel as one launch (the list's path in its first
// blocks where the list is short, else a thread a particle), one launch and one wait fewer a round: the
// search took 1,399 ms over the 10^6-ball pile's 5 s against 872 and 501 (CUPTI: the merged kernel's
// registers are the list path's), and the pile 33.5, 33.5 and 33.4 ms a frame against 33.3, 33.3 and
// 33.5 (an H200, fp32, separate binaries alternating in one call).
template <int G>
__global__ void scatterListedEventsKernel(CollisionArgs<float> a, unsigned long long* offered) {
    waitForPrimary();
    if ((a.gate && *a.gate == 0u) || !listedScatter(a)) return;
    const int64_t count = int64_t(*a.activeInCount);
    const int64_t t = int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
    const int64_t groups = int64_t(gridDim.x) * blockDim.x / G;
    const int rank = int(t % G);
    const unsigned mask = groupMask<G>();
    for (int64_t k = t / G; k < count; k += groups) {  // the group's lanes alike
        const int64_t i = a.activeIn[k];
        const Vec3<float> xi = a.p.x[i], vi = a.p.v[i];
        const float ri = a.table.radius[a.p.species[i]];
        CollisionEvent best = noEvent();
        forEachCandidateShared<G>(a.grid, a.candidates, i, xi, ri, rank,
                                  [&](int64_t j) { offerPair(a, offered, i, xi, vi, ri, j, best); });
        best = groupBest<G>(best, mask);
        if (rank == 0) {
            considerWalls(xi, vi, ri, a.box, a.window, best);
            recordEvent(a, i, best);
        }
        __syncwarp(mask);
    }
}

// Entry t of the round before's list (activeIn) loses its active flag.
template <class Real>
__device__ inline void clearListedFlag(const CollisionArgs<Real>& a, int64_t t) {
    if (t < int64_t(*a.activeInCount)) a.active[a.activeIn[t]] = 0;
}

// The inactive particles' offered events (an inactive particle has no wall event: it did not move since
// the round that found it none, or in a stage's first round it is too slow for one), their words
// cleared for the next round; with clearActiveIn, the active flags of the round before's list cleared
// too (clearActiveKernel's work, which the searches before this kernel have read).
// The flags cleared by a kernel of their own before the listed resolution: an H200, fp32, CUPTI, the
// 10^6-ball pile over 5 s: 24,347 launches of 3.6 us, each with 1.3 us of idle GPU after it. Here the
// collection took 228 ms over the 5 s against 214, and the clearing kernel's 87 ms and its waits went.
// A round that finds no event leaves the flags cleared rather than the list's (its resolution is gated
// off): no round searches after it, and the flags are set again before any search reads them (the next
// stage's launchOpenStage, or findEvents' every-particle memset; a walls-at-once stage searches nothing).
__global__ void collectOfferedEventsKernel(CollisionArgs<float> a, unsigned long long* offered) {
    waitForPrimary();
    const int64_t i = int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
    if (i >= a.p.n || (a.gate && *a.gate == 0u)) return;
    if (a.clearActiveIn) clearListedFlag(a, i);
    const unsigned long long word = offered[i];
    if (word == 0ull) return;
    offered[i] = 0ull;
    recordEvent(a, i, unpackedEvent(word));
}

// The wall event e of particle i (its partner a wall code), resolved with the particle's acceleration
// at the end of the step: moves and turns it, returns the collision kind and what the tally adds.
template <class Real>
__device__ int resolveWallOf(const CollisionArgs<Real>& a, int64_t i, const CollisionEvent& e, Vec3<Real> acceleration, double* loss,
                             double* impulse, int* impulseRow, bool* atCentre, ImpactDetail<Real>* logged) {
    const int si = a.p.species[i];
    const int code = int(-1 - e.partner), axis = code / 2;
    Vec3<Real> x = a.p.x[i], v = a.p.v[i];
    const int kind = resolveWallEvent(x[axis], v[axis], acceleration[axis], a.table.mass[si], a.table.radius[si], a.box[axis], code % 2,
                                      e.key, a.window.maxRewind, a.wallRestitution, a.elasticBelow, loss, impulse, logged);
    if (logged) logged->normal[axis] = code % 2 == 0 ? Real(1) : Real(-1);  // into the box
    *impulseRow = code;
    *atCentre = atWallCentre(x, a.table.radius[si], a.box, axis);
    a.p.x[i] = x;
    a.p.v[i] = v;
    return kind;
}

// What one resolved impact adds to its particle's rows and to the kind counts. Tried and not kept: the
// kind counts and the contact log's slots one atomic a warp (warpAggregatedAdd, Increment) instead of one
// an impact, a landing's round resolving tens of thousands: the same bits, no gain (an H200, fp32, one
// call against separate libraries: the sandbox at 10^5 balls 10.8 and 11.0 ms a landing frame in its
// impact rounds against 10.8 and 11.1, `corebox bench pile` 10^6 balls 28.48 ms a frame against 28.31).
template <class Real>
__device__ void recordImpact(const CollisionArgs<Real>& a, int64_t i, int kind, double loss, double impulse, int impulseRow, bool atCentre) {
    if (kind == kNoCollision) return;
    a.loss[i] += loss;
    a.impulses[size_t(impulseRow) * size_t(a.p.n) + size_t(i)] += impulse;  // only thread i writes row i
    if (atCentre) a.impulses[size_t(kWallCount + impulseRow) * size_t(a.p.n) + size_t(i)] += impulse;
    atomicAdd(&a.kindCounts[kind - 1], 1ull);
}

// Where the search's cells are tracked (CollisionArgs::cellKeys): particle i, moved to x, flags the cells
// stale when it left the cell its key names. Where the searches read candidate rows, it flags the next
// round's cells and rows when it has moved too far from where they were made.
template <class Real>
__device__ void flagCellChange(const CollisionArgs<Real>& a, int64_t i, const Vec3<Real>& x) {
    if (a.cellKeys && uint32_t(cellKeyOfParticle(a.grid.geometry, a.cellSplit, i, x)) != a.cellKeys[i])
        *a.cellsMoved = 1u;
    if (a.staleNext && leftCandidates(a.candidates, i, x)) *a.staleNext = 1u;
}

// Particle i's part of the resolution of the mutual-earliest events (its event e, valid): the pair by
// its lower index (as the CPU), or its wall.
template <class Real>
__device__ void resolveEventOf(const CollisionArgs<Real>& a, int64_t i, const CollisionEvent& e) {
    const int si = a.p.species[i];
    int kind = kNoCollision;
    double loss = 0, impulse = 0;
    int impulseRow = kPairVirialRow;  // or the wall's
    bool atCentre = false;
    ImpactDetail<Real> detail{};
    ImpactDetail<Real>* logged = a.log ? &detail : nullptr;  // the log off costs nothing
    if (e.partner >= 0) {
        const int64_t j = e.partner;
        if (j > i && a.events[j].partner == i) {
            const int sj = a.p.species[j];
            Vec3<Real> xi = a.p.x[i], vi = a.p.v[i], xj = a.p.x[j], vj = a.p.v[j];
            kind = resolvePairEvent(xi, vi, a.contactAcceleration[i], a.table.mass[si], xj, vj, a.contactAcceleration[j],
                                    a.table.mass[sj], a.table.radius[si] + a.table.radius[sj], e.key, a.window.maxRewind,
                                    a.restitution, a.elasticBelow, &loss, &impulse, logged);
            a.p.x[i] = xi;
            a.p.v[i] = vi;
            a.p.x[j] = xj;
            a.p.v[j] = vj;
            flagCellChange(a, i, xi);
            flagCellChange(a, j, xj);
        }
    } else {
        kind = resolveWallOf(a, i, e, a.contactAcceleration[i], &loss, &impulse, &impulseRow, &atCentre, logged);
        flagCellChange(a, i, a.p.x[i]);
    }
    recordImpact(a, i, kind, loss, impulse, impulseRow, atCentre);
    if (kind != kNoCollision && logged && loggedImpact(detail, a.logMinImpulse))
        a.log[atomicAdd(a.logCount, 1u)] = ImpactRecord<Real>{i, e.partner, a.logRound, detail};
}

// Resolves the mutual-earliest events, and leaves a particle active for the next round when it had an
// event (resolved now or still pending): the resolution reads no active flag, so the next search's
// flags are set here rather than by a launch of their own. A thread a particle, or with `listed` a
// thread an entry of this round's list of the particles with events (activeOut, counters[1] long), after
// the round before's list's flags are cleared (clearActiveKernel, or the collection where clearActiveIn):
// the flags are then that list's, as a thread a particle leaves them. One kernel for
// both, so that the resolution is the same instructions either way (in a kernel of its own the fp64
// resolution of the Lennard-Jones fluid with hard cores contracted into other fused multiply-adds, and
// its bits differed from the rounds' one by one: tests/gpu/test_cuda_contacts.cpp).
template <class Real>
__global__ void resolveKernel(CollisionArgs<Real> a, bool listed) {
    waitForPrimary();
    const int64_t t = int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
    if ((a.gate && *a.gate == 0u) || t >= (listed ? int64_t(a.counters[1]) : a.p.n)) return;
    const int64_t i = listed ? int64_t(a.activeOut[t]) : t;
    const CollisionEvent e = a.events[i];
    a.active[i] = isValid(e);
    if (isValid(e)) resolveEventOf(a, i, e);
}

// The round before's active flags (its list, activeIn) cleared: a particle with an event this round is
// set again by the listed resolution, which runs after.
template <class Real>
__global__ void clearActiveKernel(CollisionArgs<Real> a) {
    const int64_t t = int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
    if (!(a.gate && *a.gate == 0u)) clearListedFlag(a, t);
}

// Walls only: particle i's wall impacts in turn (launchResolveWallImpacts).
template <class Real>
__device__ void resolveWallsOf(const CollisionArgs<Real>& a, int64_t i, const Vec3<Real>* acceleration, Real contactGap,
                               const Vec3<Real>* xBuilt, Real halfSkin2, unsigned int* stats) {
    const int si = a.p.species[i];
    const Real radius = a.table.radius[si];
    unsigned impacts = 0;
    // At most one impact per wall plane an axis: a rebound puts the centre inside on that axis, and the
    // opposite wall is a box length away.
    for (int k = 0; k < 2 * 3; ++k) {
        CollisionEvent e = noEvent();
        considerWalls(a.p.x[i], a.p.v[i], radius, a.box, a.window, e);
        if (!isValid(e)) break;
        double loss = 0, impulse = 0;
        int impulseRow = kPairVirialRow;
        bool atCentre = false;
        const int kind = resolveWallOf(a, i, e, acceleration[i], &loss, &impulse, &impulseRow, &atCentre,
                                       static_cast<ImpactDetail<Real>*>(nullptr));
        recordImpact(a, i, kind, loss, impulse, impulseRow, atCentre);
        a.hasContactAcceleration[i] = 1;  // its impact rows are written: the tally reads them, the next stage clears them
        ++impacts;
    }
    const Vec3<Real> x = a.p.x[i];
    if (impacts > 0) {
        atomicMax(&stats[0], impacts);
        if (xBuilt && !(norm2(x - xBuilt[i]) <= halfSkin2)) stats[2] = 1u;
    }
    const bool finite = isfinite(x.x) && isfinite(x.y) && isfinite(x.z);
    if (!finite || deepestWallApproach(x, screenReach(radius, contactGap), a.box) > Real(0)) stats[1] = 1u;
}

template <class Real>
__global__ void resolveWallImpactsKernel(CollisionArgs<Real> a, const Vec3<Real>* acceleration, Real contactGap, const Vec3<Real>* xBuilt,
                                         Real halfSkin2, unsigned int* stats) {
    const int64_t i = int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
    if (i < a.p.n) resolveWallsOf(a, i, acceleration, contactGap, xBuilt, halfSkin2, stats);
}

// The one-wait step's stage (launchStageWalls): the verdict read from the screen by every thread, the
// stage opened and its walls resolved where it is WallsOnly, then the step check and forecast of each particle.
template <class Real>
__global__ void stageWallsKernel(CollisionArgs<Real> a, const Vec3<Real>* acceleration, Real contactGap, const Vec3<Real>* xBuilt,
                                 Real halfSkin2, StageOpening<Real> o) {
    const int64_t i = int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
    if (i >= a.p.n) return;
    StepWords* w = o.words;
    const unsigned screen[3] = {w->screen[0], w->screen[1], w->screen[2]};
    const StageScreen verdict = screenVerdict(screen, o.scales);
    if (i == 0) w->stage = unsigned(verdict);
    if (verdict == StageScreen::WallsOnly) {
        if (a.hasContactAcceleration[i]) {  // as beginCollisions clears the rows the last stage wrote
            for (int r = 0; r <= kImpulseRows; ++r) a.impulses[size_t(r) * size_t(a.p.n) + size_t(i)] = 0;
            a.hasContactAcceleration[i] = 0;
        }
        resolveWallsOf(a, i, acceleration, contactGap, xBuilt, halfSkin2, w->wallStats);
        if (a.hasContactAcceleration[i]) o.moved[warpAggregatedIncrement(&w->wallMoved)] = int32_t(i);
        const Vec3<Real> x = a.p.x[i], v = a.p.v[i];
        const Real radius = a.table.radius[a.p.species[i]];
        bool contact = false;
        for (int axis = 0; axis < 3; ++axis)
            for (int side = 0; side < 2; ++side) contact = contact || wallContactActive(x[axis], v[axis], radius, a.box[axis], side, o.resting);
        if (contact) atomicAdd(&w->wallContacts, 1u);
    }
    checkParticle(HealthArgs<Real>{a.p, a.box, w->healthCounts, w->healthExamples}, a.table, i, o.kineticRow);
    if (o.forecast.moves) forecastParticle(o.forecast, i, a.p.x[i], a.p.v[i], acceleration[i]);
}

}  // namespace

template <class Real>
void launchOpenStage(const StageOpenArgs<Real>& a, cudaStream_t stream) {
    const int64_t threads = std::max<int64_t>({a.n, a.zeroCount, 3});
    openStageKernel<<<blocksFor(threads), kBlock, 0, stream>>>(a);
    checkLaunch("open stage kernel");
}

template <class Real>
void launchFindEvents(const CollisionArgs<Real>& a, cudaStream_t stream) {
    switch (searchGroupFor(a.p.n)) {
        case 32:
            launchDependent(findEventsKernel<Real, 32>, blocksFor(a.p.n * 32), stream, "event kernel", a);
            break;
        case 8:
            launchDependent(findEventsKernel<Real, 8>, blocksFor(a.p.n * 8), stream, "event kernel", a);
            break;
        default:
            launchDependent(findEventsKernel<Real, 1>, blocksFor(a.p.n), stream, "event kernel", a);
    }
}

bool searchWalksAlone(int64_t n) { return searchGroupFor(n) == 1; }

namespace {
void launchListedScatter(const CollisionArgs<float>& a, unsigned long long* offered, cudaStream_t stream) {
    if (!a.activeIn || a.listedScatterMax <= 0) return;
    static_assert(kBlock % kListedScatterLanes == 0, "a block holds whole groups");
    static const int resident = residentBlocks(scatterListedEventsKernel<kListedScatterLanes>);
    // Groups for the longest list the kernel takes (at least one: the other searches leave such a round to it).
    const int64_t groups = std::max<int64_t>(1, std::min<int64_t>(a.listedScatterMax, a.p.n / kListedScatterShare));
    const int64_t blocks = std::min<int64_t>(resident, blocksFor(groups * kListedScatterLanes));
    launchDependent(scatterListedEventsKernel<kListedScatterLanes>, unsigned(blocks), stream,
                    "listed scattered event kernel", a, offered);
}
}  // namespace

// A round's searches, collection and resolution go as programmatic dependent launches (gpu_common.cuh
// launchDependent): each kernel's launch is made while the one before ends. An H200, fp32, the sandbox
// example at 10^5 balls, separate libraries alternating in one call: its landing's impact rounds 9.8 and
// 9.9 ms a frame against 11.0 and 10.7, the landing's frames 19.5 and 19.6 ms against 20.8 and 20.2, the
// same state hash; `corebox bench pile` 10^6 balls 28.4 ms a frame against 28.5, the same energies.
void launchSparseOrFullSearch(const CollisionArgs<float>& a, unsigned long long* offered, cudaStream_t stream) {
    if (a.p.n == 0) return;
    launchListedScatter(a, offered, stream);
    launchFindEvents(a, stream);
    launchDependent(collectOfferedEventsKernel, blocksFor(a.p.n), stream, "offered event kernel", a, offered);
}

void launchScatteredSearch(const CollisionArgs<float>& a, unsigned long long* offered, cudaStream_t stream) {
    if (a.p.n == 0) return;
    launchListedScatter(a, offered, stream);
    scatterEventsKernel<<<blocksFor(a.p.n), kBlock, 0, stream>>>(a, offered);
    checkLaunch("scattered event kernel");
    launchDependent(collectOfferedEventsKernel, blocksFor(a.p.n), stream, "offered event kernel", a, offered);
}

template <class Real>
void launchMarkSearchers(const CollisionArgs<Real>& a, cudaStream_t stream) {
    if (a.p.n == 0) return;
    markSearchersKernel<Real><<<blocksFor(a.p.n), kBlock, 0, stream>>>(a);
    checkLaunch("searcher marking kernel");
}

template <class Real>
void launchResolve(const CollisionArgs<Real>& a, cudaStream_t stream) {
    launchDependent(resolveKernel<Real>, blocksFor(a.p.n), stream, "resolve kernel", a, false);
}

template <class Real>
void launchResolveListed(const CollisionArgs<Real>& a, cudaStream_t stream) {
    if (a.p.n == 0) return;
    if (!a.clearActiveIn) {
        clearActiveKernel<Real><<<blocksFor(a.p.n), kBlock, 0, stream>>>(a);
        checkLaunch("active flags kernel");
    }
    launchDependent(resolveKernel<Real>, blocksFor(a.p.n), stream, "listed resolve kernel", a, true);
}

template <class Real>
void launchResolveWallImpacts(const CollisionArgs<Real>& a, const Vec3<Real>* acceleration, Real contactGap, const Vec3<Real>* xBuilt,
                              Real halfSkin2, unsigned int* stats, cudaStream_t stream) {
    if (a.p.n <= 0) return;
    resolveWallImpactsKernel<Real><<<blocksFor(a.p.n), kBlock, 0, stream>>>(a, acceleration, contactGap, xBuilt, halfSkin2, stats);
    checkLaunch("wall impacts kernel");
}

template <class Real>
void launchStageWalls(const CollisionArgs<Real>& a, const Vec3<Real>* acceleration, Real contactGap, const Vec3<Real>* xBuilt,
                      Real halfSkin2, const StageOpening<Real>& opening, cudaStream_t stream) {
    if (a.p.n <= 0) return;
    stageWallsKernel<Real><<<blocksFor(a.p.n), kBlock, 0, stream>>>(a, acceleration, contactGap, xBuilt, halfSkin2, opening);
    checkLaunch("stage walls kernel");
}

#define COREBOX_INSTANTIATE(Real)                                                                                      \
    template void launchResolveWallImpacts<Real>(const CollisionArgs<Real>&, const Vec3<Real>*, Real,                  \
                                                 const Vec3<Real>*, Real, unsigned int*, cudaStream_t);                \
    template void launchStageWalls<Real>(const CollisionArgs<Real>&, const Vec3<Real>*, Real, const Vec3<Real>*, Real, \
                                         const StageOpening<Real>&, cudaStream_t);                                     \
    template void launchOpenStage<Real>(const StageOpenArgs<Real>&, cudaStream_t);                                     \
    template void launchFindEvents<Real>(const CollisionArgs<Real>&, cudaStream_t);                                    \
    template void launchMarkSearchers<Real>(const CollisionArgs<Real>&, cudaStream_t);                                 \
    template void launchResolve<Real>(const CollisionArgs<Real>&, cudaStream_t);                                       \
    template void launchResolveListed<Real>(const CollisionArgs<Real>&, cudaStream_t);
COREBOX_INSTANTIATE(float)
COREBOX_INSTANTIATE(double)
#undef COREBOX_INSTANTIATE

}  // namespace corebox::gpu
