// The contact relaxation on the GPU (contact_relaxation.h): per-particle contact lists built from the
// cell list in the order the CPU builds them (count, scan, fill, each contact's warm-start impulse
// from the last step's rows), the warm start, then either the coloured Gauss-Seidel sweeps of
// contact_gauss_seidel.cu or the accelerated Jacobi sweeps here, one thread per particle
// (relaxParticle, sweepMomentum). No order-dependent atomics: a Jacobi sweep reads only the previous
// sweep's state, and the residual is a maximum (contact_residual.cuh).
#include <cooperative_groups.h>
#include <cub/device/device_scan.cuh>

#include <algorithm>

#include "gpu_common.cuh"
#include "gpu_launch.h"
#include "contact_residual.cuh"
#include "neighbour_walk.cuh"
#include "packed_body.cuh"

namespace corebox::gpu {
namespace {

// Whether pair (i, j) is a contact the relaxation acts on. The count and the fill read the packed bodies
// (launchPackBodies, by the count): a neighbour's position with its radius and its velocity, a vector
// read each.
template <class Real>
__device__ bool isPairContact(const ContactArgs<Real>& a, int64_t i, const Vec3<Real>& xi, const Vec3<Real>& vi, Real ai, int64_t j) {
    if (j == i) return false;
    const PackedBody<Real> xj = xBody(a, j);
    return pairContactActive(xi, vi, vec3Of(xj), vec3Of(vBody(a, j)), ai + xj.w, a.resting);
}

// fn(wall code) for each wall contact of the particle at xi, in wall order; returns their count.
template <class Real, class Fn>
__device__ int forEachWallContact(const ContactArgs<Real>& a, const Vec3<Real>& xi, const Vec3<Real>& vi, Real ai, Fn&& fn) {
    int count = 0;
    for (int axis = 0; axis < 3; ++axis) {
        for (int side = 0; side < 2; ++side) {
            if (!wallContactActive(xi[axis], vi[axis], ai, a.box[axis], side, a.resting)) continue;
            fn(wallCode(axis, side));
            ++count;
        }
    }
    return count;
}

// fn(partner) for each contact of particle i the relaxation acts on, in list order (cell-list
// neighbours, then walls), as the CPU lists them.
template <class Real, class Fn>
__device__ int forEachContact(const ContactArgs<Real>& a, int64_t i, Fn&& fn) {
    int count = 0;
    const PackedBody<Real> bxi = xBody(a, i);
    const Vec3<Real> xi = vec3Of(bxi), vi = vec3Of(vBody(a, i));
    const Real ai = bxi.w;
    forEachNeighbour(a.cells, xi, ai, [&](int64_t j) {
        if (!isPairContact(a, i, xi, vi, ai, j)) return;
        fn(j);
        ++count;
    });
    return count + forEachWallContact(a, xi, vi, ai, fn);
}

// G lanes a particle (neighbour_walk.cuh; G = 1: a thread walks alone), whole groups in a block.
template <class Real, int G>
__global__ void countContactsKernel(ContactArgs<Real> a, unsigned long long* total) {
    const int64_t t = int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
    const int64_t k = t / G;
    const int rank = int(t % G);
    if (t == 0) a.contactStart[0] = 0;
    if (k >= a.p.n) return;
    const int64_t i = a.cells.sorted[k];  // in cell order, as findEventsKernel
    int64_t count = 0;
    if (G == 1) {
        // The list gathered here and stored a 16-byte vector at a time: a store a contact put each warp's
        // stores in 32 places at once, several of them in one sector (the settled 10^6-ball pile's count,
        // as the fill above: 277 us against 286).
        static_assert(kListedPartners % 4 == 0, "a particle's listed contacts are whole int4");
        alignas(16) int32_t listed[kListedPartners];
        int c = 0;
        count = forEachContact(a, i, [&](int64_t partner) {
            if (c < kListedPartners) listed[c] = int32_t(partner);
            ++c;
        });
        if (a.partnerScratch) {
            int4* out = reinterpret_cast<int4*>(a.partnerScratch + size_t(i) * kListedPartners);
            for (int q = 0; 4 * q < c && q < kListedPartners / 4; ++q)
                out[q] = reinterpret_cast<const int4*>(listed)[q];
        }
    } else {
        const PackedBody<Real> bxi = xBody(a, i);
        const Vec3<Real> xi = vec3Of(bxi), vi = vec3Of(vBody(a, i));
        const Real ai = bxi.w;
        int pairs = 0;
        forEachNeighbourShared<G>(a.cells, xi, ai, rank, [&](int64_t j) { pairs += isPairContact(a, i, xi, vi, ai, j) ? 1 : 0; });
        for (int offset = G / 2; offset > 0; offset /= 2) pairs += __shfl_xor_sync(groupMask<G>(), pairs, offset);
        if (rank != 0) return;
        count = pairs + forEachWallContact(a, xi, vi, ai, [](int64_t) {});
    }
    a.contactStart[i + 1] = count;
    // The total, one atomic a warp: an atomic a particle queued every particle with a contact on one address
    // (an H200, fp32, CUPTI kernel times: the sandbox example at 10^5 balls, whose counts behind the impact
    // rounds take a total, 34.9 us a count against 68.1, its GPU busy 2122 ms against 2210; the same bits).
    if (total) warpAggregatedAdd(total, unsigned(count));
}

// Particle i's row for `partner` in the last step's rows, or -1. The search starts at *from (wrapping
// round) and leaves it after the row found, which is the same row from any start (a particle lists a
// partner once): a particle's contacts come in the order they came the step before, unless the cells
// changed, so lookups made in turn take about one read each. The fill's rows, a thread each, start each
// lookup at the particle's first row (fillContactsKernel).
template <class Real>
__device__ int64_t warmRowOf(const ContactArgs<Real>& a, int64_t i, int64_t partner, int64_t& from) {
    const int64_t begin = a.warmStart[i], end = a.warmStart[i + 1];
    if (from < begin || from >= end) from = begin;
    for (int64_t k = from; k < end; ++k) {
        if (a.warmPartner[k] != partner) continue;
        from = k + 1;
        return k;
    }
    for (int64_t k = begin; k < from; ++k) {
        if (a.warmPartner[k] != partner) continue;
        from = k + 1;
        return k;
    }
    return -1;
}

// The normal speed an isolated contact's Gauss-Seidel update aims at (isolatedContactTarget).
template <class Real>
__device__ Real contactTarget(const ContactArgs<Real>& a, int64_t i, int64_t partner) {
    const Vec3<Real> xi = vec3Of(xBody(a, i)), vi = vec3Of(vBody(a, i));
    Real vn = 0, e = 0;
    if (isWallContact(partner)) {
        const int code = int(-1 - partner);
        vn = (code % 2 == 0 ? Real(1) : Real(-1)) * vi[code / 2];
        e = a.bounce.wallRestitution;
    } else {
        const Vec3<Real> r = xi - vec3Of(xBody(a, partner));
        const Real dist = realSqrt(norm2(r));
        vn = dist > Real(0) ? dot(vi - vec3Of(vBody(a, partner)), r) / dist : Real(0);
        e = a.bounce.restitution;
    }
    return isolatedContactTarget(vn, e, a.bounce);
}

// Particle i's own impulse rows (no atomics): summed in a fixed order when asked.
template <class Real>
__device__ void addImpulseRows(const ContactArgs<Real>& a, int64_t i, const ImpulseSums& given) {
    const size_t n = size_t(a.p.n);
    for (int k = 0; k < kWallCount; ++k) {
        if (given.wall[k] != 0) a.impulses[size_t(k) * n + size_t(i)] += given.wall[k];
        if (given.wallCentre[k] != 0) a.impulses[size_t(kWallCount + k) * n + size_t(i)] += given.wallCentre[k];
    }
    if (given.pairVirial != 0) a.impulses[size_t(kPairVirialRow) * n + size_t(i)] += given.pairVirial;
}

// Row `slot` of particle i (count rows), with `partner`: the partner, the target of an isolated contact, the
// warm start's impulse and the kept colour. `warmFrom`: where the lookup in the warm rows starts
// (warmRowOf; the row found is the same from anywhere).
template <class Real>
__device__ void fillRow(const ContactArgs<Real>& a, int64_t i, int count, int64_t slot, int64_t partner,
                        int64_t& warmFrom) {
    a.partner[slot] = partner;
    // An isolated contact may bounce. Jacobi (relaxParticle) decides it sweep by sweep: nothing to
    // warm-start. Gauss-Seidel decides it here (contactTarget) and warm-starts it unless it bounces,
    // as the CPU does. Both rows of a pair decide alike (both counts are 1, or not; vn is symmetric).
    const bool isolated =
        count == 1 && (isWallContact(partner) || a.contactStart[partner + 1] - a.contactStart[partner] == 1);
    const Real target = a.gaussSeidel && isolated ? contactTarget(a, i, partner) : Real(0);
    if (a.gaussSeidel) a.target[slot] = target;
    const bool warm = a.warm && (a.gaussSeidel ? !(target > Real(0)) : !isolated);
    // An own row (the pair's lower index, or a wall) keeps its pair's colour from the warm rows,
    // where their own row was the same pair's (and pushed, where keepPushedColoursOnly).
    const bool recolour = a.warm && a.prevColour && (isWallContact(partner) || partner > i);
    const int64_t warmRow = warm || recolour ? warmRowOf(a, i, partner, warmFrom) : -1;
    a.lambda[slot] = warm && warmRow >= 0 ? a.warmLambda[warmRow] : Real(0);
    a.applied[slot] = a.lambda[slot];
    const bool kept = recolour && warmRow >= 0 && (!a.keepPushedColoursOnly || a.warmLambda[warmRow] > Real(0));
    if (a.prevColour) a.prevColour[slot] = kept ? a.warmColour[warmRow] : kUncolouredRow;
}

// Where the count listed a particle's contacts (ContactArgs::partnerScratch) the fill copies them
// instead of walking the cells again: on the settled 10^6-ball pile (ncu, H200, fp32) the fill took 0.24
// ms instead of 1.55 and the count 0.41 instead of 0.29; `corebox bench pile` (same call, the same bits)
// 97.2 ms a frame instead of 105.9 (the last second 53.8 instead of 59.1), 10^5 balls 27.1 instead of 27.8.
// A block takes kBlock consecutive particles: their listed rows a thread a row (its particle found among
// the block's row starts in shared memory), so that a warp's stores are to neighbouring rows; a particle
// the count did not list (more than kListedPartners contacts) walked by a thread of its own. Before, a
// thread a particle filled its rows one after another, each store of a warp to 32 rows apart: the
// settled 10^6-ball pile (an H200, fp32, CUPTI, the median listing of the last 1.25 s) 152 us against 272.
template <class Real>
__global__ void __launch_bounds__(kBlock) fillContactsKernel(ContactArgs<Real> a) {
    __shared__ int64_t starts[kBlock + 1];
    const int64_t first = int64_t(blockIdx.x) * kBlock;
    const int particles = stageRowStarts(starts, a.contactStart, first, a.p.n);
    auto listed = [&](int count) { return a.partnerScratch != nullptr && count <= kListedPartners; };
    // Without the count's lists every particle is walked (below).
    for (int64_t s = starts[0] + threadIdx.x; a.partnerScratch && s < starts[particles]; s += kBlock) {
        const int lo = particleOfRow(starts, particles, s);
        const int count = int(starts[lo + 1] - starts[lo]);
        if (!listed(count)) continue;
        const int64_t i = first + lo;
        int64_t warmFrom = -1;
        fillRow(a, i, count, s, int64_t(a.partnerScratch[size_t(i) * kListedPartners + size_t(s - starts[lo])]),
                warmFrom);
    }
    if (int(threadIdx.x) >= particles) return;
    const int count = int(starts[threadIdx.x + 1] - starts[threadIdx.x]);
    if (listed(count)) return;
    const int64_t i = first + threadIdx.x;
    int64_t slot = starts[threadIdx.x], warmFrom = -1;
    forEachContact(a, i, [&](int64_t partner) { fillRow(a, i, count, slot++, partner, warmFrom); });
}

template <class Real>
__global__ void dropBounceImpulsesKernel(Real* lambda, const Real* target, int64_t rows) {
    const int64_t s = int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
    if (s < rows && target[s] > Real(0)) lambda[s] = Real(0);
}

// Impulses on particle i's rows, no sweep: the warm start (each row's lambda, which it begins with) or,
// with `settle`, the end of the accelerated sweeps (settleRow). Reads positions only: no hazard
// between particles.
template <class Real>
__global__ void rowImpulsesKernel(ContactArgs<Real> a, bool settle) {
    const int64_t i = int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
    if (i >= a.p.n) return;
    const int64_t first = a.contactStart[i];
    const int count = int(a.contactStart[i + 1] - first);
    if (count == 0) return;
    ImpulseSums given;
    Real* lambda = a.lambda + first;
    Real* applied = a.applied + first;
    auto partner = [&](int c) { return a.partner[first + c]; };
    if (settle) {
        a.p.v[i] += rowImpulsesOf(i, count, partner, [&](int c) { return settleRow(lambda[c], applied[c]); }, a.p.x, a.p.species, a.table.mass,
                                  a.table.radius, a.box, given);
    } else {
        a.p.v[i] += rowImpulsesOf(i, count, partner, [&](int c) { return lambda[c]; }, a.p.x, a.p.species, a.table.mass, a.table.radius, a.box,
                                  given);
    }
    addImpulseRows(a, i, given);
}

// A sweep's impulses on particle i (relaxParticle's `given`), added to its rows as they come: an
// ImpulseSums of 13 doubles indexed by wall code lived in local memory (a 104-byte stack frame), read
// and written every sweep. Each wall has at most one contact with i, so a row receives the same sum,
// the same bits (the CUDA dense-contact and pile tests pass unchanged on an H200).
struct SweepImpulseRows {
    double* rows;
    size_t n, i;
    double pairVirial = 0;
    __device__ void addWall(int code, double impulse, bool atCentre) {
        rows[size_t(code) * n + i] += impulse;
        if (atCentre) rows[size_t(kWallCount + code) * n + i] += impulse;
    }
};

// One Jacobi sweep's update of particle i into dv[i], dx[i] (relaxParticle), its pair impulses added to
// its virial row; returns its residual.
template <class Real>
__device__ ContactResidual<Real> sweepParticle(const ContactArgs<Real>& a, int64_t i, Real beta) {
    ContactResidual<Real> r{0, 0};
    const int64_t first = a.contactStart[i];
    const int count = int(a.contactStart[i + 1] - first);
    SweepImpulseRows given{a.impulses, size_t(a.p.n), size_t(i)};
    auto contactsOf = [&](int64_t j) { return int(a.contactStart[j + 1] - a.contactStart[j]); };
    relaxParticle(i, count, [&](int c) { return a.partner[first + c]; }, contactsOf, a.lambda + first, a.p.x, a.p.v, a.p.species,
                  a.table.mass, a.table.radius, a.box, a.up, a.bounce, a.dv[i], a.dx[i], r, given, a.applied + first, beta);
    if (given.pairVirial != 0) a.impulses[size_t(kPairVirialRow) * size_t(a.p.n) + size_t(i)] += given.pairVirial;
    return r;
}

// `measure`: the batch's last sweep, whose residual is read.
// Four threads a particle, each taking every fourth contact, made the 10^5-ball pile's sweep slower (35
// us against 20: its L2 traffic went from 22% to 67% of peak), though faster at 10^4 balls.
template <class Real>
__global__ void sweepKernel(ContactArgs<Real> a, bool measure, Real beta) {
    const int64_t i = int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
    ContactResidual<Real> r{0, 0};
    if (i < a.p.n) r = sweepParticle(a, i, beta);
    if (measure) addResidual(r, a.residual);  // the same for the whole grid: every lane of a warp reaches the shuffles
}

template <class Real>
__global__ void applySweepKernel(ContactArgs<Real> a) {
    const int64_t i = int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
    if (i >= a.p.n) return;
    a.p.v[i] += a.dv[i];
    a.p.x[i] += a.dx[i];
}

// A listing's whole relaxation in one cooperative launch, on the schedule of RelaxationPlan: each sweep
// (every thread a stride of particles), a grid-wide barrier, the update, a barrier. The residual is
// taken in the sweeps the plan looks at (each thread's maxima over its particles, then one atomic a
// block) into one of two slots, a check in each in turn, the other cleared for the next; after the
// barrier every thread reads it and decides alike. The sweeps and their order are those of the launches one by one
// (launchRelaxContacts), so the result is the same bits; what goes is a launch pair a sweep and a host
// round trip a batch. Measured (`corebox bench pile`, H200, fp32, 5 s, the same run with both): the
// contact phase of the 10^4-ball pile (126 sweeps a step) took 10.5 ms a frame instead of 12.3, of
// 10^5 balls (233) 32.1 instead of 34.9, of 10^6 (288) 404 instead of 419; whole frames 18.9, 46.0
// and 447 ms instead of 21.0, 48.9 and 462. The sweeps themselves are the cost where they are many
// particles (a sweep of 10^6 reads some 500 bytes a particle); at 10^4 a sweep is a chain of
// dependent loads a contact long, on few threads. ncu (an H100, a listing of the 10^6-ball pile): 78
// registers a thread hold the kernel to 3 blocks an SM (37.5% occupancy), 1.06 TB/s, L2 hits 61%;
// bounded to 4 blocks an SM (64 registers) it spilled and the 10^6-ball pile's frames took twice as
// long (an H200: 872 against 446 ms; 10^5 balls 46.4 against 43.3). Fewer bytes a contact (the rows
// column-major, the partner's contact count kept in the row) is the lever left.
// words: [0..3] the two residual slots, [4..5] the first sweep's residual, [6..7] the last's (double
// bits), [8] the sweeps run.
template <class Real>
__global__ void __launch_bounds__(kBlock) relaxListingKernel(ContactArgs<Real> a, RelaxationPlan plan, unsigned long long* words) {
    cooperative_groups::grid_group grid = cooperative_groups::this_grid();
    const int64_t first = int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
    const int64_t stride = int64_t(gridDim.x) * blockDim.x;
    const int64_t n = a.p.n;
    int done = 0, checks = 0;
    double firstOverlap = 0;  // the first sweep's, from its check on
    for (;;) {
        unsigned long long* slot = words + 2 * (checks % 2);
        const Real beta = sweepMomentum<Real>(done);
        const bool measured = plan.checkedAfter(done + 1, firstOverlap);
        double speed = 0, overlap = 0;
        for (int64_t i = first; i < n; i += stride) {
            const ContactResidual<Real> r = sweepParticle(a, i, beta);
            speed = fmax(speed, double(r.speedChange));
            overlap = fmax(overlap, double(r.overlap));
        }
        if (measured) addBlockResidual(speed, overlap, slot);
        grid.sync();
        for (int64_t i = first; i < n; i += stride) {
            a.p.v[i] += a.dv[i];
            a.p.x[i] += a.dx[i];
        }
        ++done;
        const bool stop = measured && checkListingResidual(plan, done, checks, slot, words, first == 0, &firstOverlap);
        grid.sync();
        if (stop) return;
    }
}

template <class Real>
__global__ void liftWorkKernel(ParticleArrays<Real> p, SpeciesTable<Real> table, const Vec3<Real>* xListed, double* row) {
    const int64_t i = int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
    if (i >= p.n) return;
    const int s = p.species[i];
    const double m = double(table.mass[s]);
    row[i] = -m * dot(vec3Cast<double>(table.field[s]), vec3Cast<double>(p.x[i]) - vec3Cast<double>(xListed[i]));
}

// The contact phase's copy of the state (ContactArgs::body) from X, V and the species, and back.
template <class Real>
__global__ void packBodiesKernel(ContactArgs<Real> a) {
    const int64_t i = int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
    if (i >= a.p.n) return;
    const int s = a.p.species[i];
    xBody(a, i) = packed(a.p.x[i], a.table.radius[s]);
    vBody(a, i) = packed(a.p.v[i], a.table.mass[s]);
}

template <class Real>
__global__ void unpackBodiesKernel(ContactArgs<Real> a) {
    const int64_t i = int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
    if (i >= a.p.n) return;
    a.p.x[i] = vec3Of(xBody(a, i));
    a.p.v[i] = vec3Of(vBody(a, i));
}

}  // namespace

bool contactCountListsPartners(int64_t n) { return n <= INT32_MAX && searchGroupFor(n) == 1; }

template <class Real>
void launchPackBodies(const ContactArgs<Real>& a, cudaStream_t stream) {
    if (a.p.n == 0) return;
    packBodiesKernel<Real><<<blocksFor(a.p.n), kBlock, 0, stream>>>(a);
    checkLaunch("contact body packing kernel");
}

template <class Real>
void launchUnpackBodies(const ContactArgs<Real>& a, cudaStream_t stream) {
    if (a.p.n == 0) return;
    unpackBodiesKernel<Real><<<blocksFor(a.p.n), kBlock, 0, stream>>>(a);
    checkLaunch("contact body unpacking kernel");
}

template <class Real>
void launchCountContacts(const ContactArgs<Real>& a, cudaStream_t stream, unsigned long long* total) {
    const int64_t n = a.p.n > 0 ? a.p.n : 1;  // one thread at least: contactStart[0]
    launchPackBodies(a, stream);
    switch (searchGroupFor(n)) {
        case 32: countContactsKernel<Real, 32><<<blocksFor(n * 32), kBlock, 0, stream>>>(a, total); break;
        case 8: countContactsKernel<Real, 8><<<blocksFor(n * 8), kBlock, 0, stream>>>(a, total); break;
        default: countContactsKernel<Real, 1><<<blocksFor(n), kBlock, 0, stream>>>(a, total);
    }
    checkLaunch("contact count kernel");
}

size_t contactScanScratchBytes(int64_t n) {
    size_t bytes = 0;
    cub::DeviceScan::InclusiveSum(nullptr, bytes, static_cast<int64_t*>(nullptr), static_cast<int64_t*>(nullptr), n + 1);
    return bytes;
}

void scanContactCounts(int64_t* contactStart, int64_t n, void* scratch, size_t scratchBytes, cudaStream_t stream) {
    // contactStart[0] = 0 and contactStart[i + 1] = count_i: the inclusive sum gives the offsets.
    cub::DeviceScan::InclusiveSum(scratch, scratchBytes, contactStart, contactStart, n + 1, stream);
    checkLaunch("contact scan");
}

template <class Real>
void launchFillContacts(const ContactArgs<Real>& a, cudaStream_t stream) {
    if (a.p.n == 0) return;
    fillContactsKernel<Real><<<blocksFor(a.p.n), kBlock, 0, stream>>>(a);
    checkLaunch("contact fill kernel");
}

template <class Real>
void launchDropBounceImpulses(Real* lambda, const Real* target, int64_t rows, cudaStream_t stream) {
    if (rows == 0) return;
    dropBounceImpulsesKernel<Real><<<blocksFor(rows), kBlock, 0, stream>>>(lambda, target, rows);
    checkLaunch("contact bounce-drop kernel");
}

template <class Real>
void launchWarmStart(const ContactArgs<Real>& a, cudaStream_t stream) {
    if (a.p.n == 0) return;
    rowImpulsesKernel<Real><<<blocksFor(a.p.n), kBlock, 0, stream>>>(a, false);
    checkLaunch("contact warm-start kernel");
}

template <class Real>
void launchSettleContacts(const ContactArgs<Real>& a, cudaStream_t stream) {
    if (a.p.n == 0) return;
    rowImpulsesKernel<Real><<<blocksFor(a.p.n), kBlock, 0, stream>>>(a, true);
    checkLaunch("contact settle kernel");
}

template <class Real>
void launchRelaxContacts(const ContactArgs<Real>& a, int sweeps, int firstSweep, cudaStream_t stream) {
    if (a.p.n == 0) return;
    for (int sweep = 0; sweep < sweeps; ++sweep) {
        // The residual of the last sweep only: cleared before it.
        const bool last = sweep == sweeps - 1;
        if (last) cudaMemsetAsync(a.residual, 0, 2 * sizeof(unsigned long long), stream);
        static_assert(kBlock % 32 == 0, "whole warps: the residual's shuffles");
        sweepKernel<Real><<<blocksFor(a.p.n), kBlock, 0, stream>>>(a, last, sweepMomentum<Real>(firstSweep + sweep));
        checkLaunch("contact sweep kernel");
        applySweepKernel<Real><<<blocksFor(a.p.n), kBlock, 0, stream>>>(a);
        checkLaunch("contact update kernel");
    }
}

template <class Real>
bool launchRelaxListing(const ContactArgs<Real>& a, const RelaxationPlan& plan, unsigned long long* words, cudaStream_t stream) {
    if (a.p.n == 0 || plan.maxSweeps < 1 || plan.batch < 1) return false;
    // As many blocks as can be resident at once (a cooperative launch needs every block running), no
    // more than the particles need.
    static const int resident = cooperativeResidentBlocks(relaxListingKernel<Real>);
    if (resident < 1) return false;
    const int64_t blocks = std::min<int64_t>(resident, blocksFor(a.p.n));
    const cudaError_t cleared = cudaMemsetAsync(words, 0, 4 * sizeof(unsigned long long), stream);
    if (cleared != cudaSuccess) throw DeviceError(std::string("contact relaxation words: ") + cudaGetErrorString(cleared));
    ContactArgs<Real> args = a;
    RelaxationPlan schedule = plan;
    void* params[] = {&args, &schedule, &words};
    const cudaError_t e = cudaLaunchCooperativeKernel(reinterpret_cast<const void*>(relaxListingKernel<Real>), dim3(unsigned(blocks)),
                                                      dim3(kBlock), params, 0, stream);
    if (e != cudaSuccess) throw DeviceError(std::string("contact relaxation kernel: ") + cudaGetErrorString(e));
    return true;
}

template <class Real>
void launchLiftWorkRow(const ParticleArrays<Real>& p, SpeciesTable<Real> table, const Vec3<Real>* xListed, double* row,
                       cudaStream_t stream) {
    if (p.n == 0) return;
    liftWorkKernel<Real><<<blocksFor(p.n), kBlock, 0, stream>>>(p, table, xListed, row);
    checkLaunch("lift work kernel");
}

#define COREBOX_INSTANTIATE(Real)                                                                                  \
    template void launchPackBodies<Real>(const ContactArgs<Real>&, cudaStream_t);                                                         \
    template void launchUnpackBodies<Real>(const ContactArgs<Real>&, cudaStream_t);                                                       \
    template void launchCountContacts<Real>(const ContactArgs<Real>&, cudaStream_t, unsigned long long*);                               \
    template void launchFillContacts<Real>(const ContactArgs<Real>&, cudaStream_t);                                \
    template void launchWarmStart<Real>(const ContactArgs<Real>&, cudaStream_t);                                   \
    template void launchDropBounceImpulses<Real>(Real*, const Real*, int64_t, cudaStream_t);                       \
    template void launchSettleContacts<Real>(const ContactArgs<Real>&, cudaStream_t);                              \
    template void launchRelaxContacts<Real>(const ContactArgs<Real>&, int, int, cudaStream_t);                     \
    template bool launchRelaxListing<Real>(const ContactArgs<Real>&, const RelaxationPlan&, unsigned long long*, cudaStream_t); \
    template void launchLiftWorkRow<Real>(const ParticleArrays<Real>&, SpeciesTable<Real>, const Vec3<Real>*, double*, cudaStream_t);
COREBOX_INSTANTIATE(float)
COREBOX_INSTANTIATE(double)
#undef COREBOX_INSTANTIATE

}  // namespace corebox::gpu
