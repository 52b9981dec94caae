// All-pairs forces in shared-memory tiles (Nyland, Harris & Prins, GPU Gems 3 ch. 31): each block
// stages blockDim (position, species) entries of the j particles in shared memory and every thread
// sums the forces on its rows over the tile. LJ needs only 1/R^2 (pair_potential.h): no sqrt in the
// loop except for the force-shifted cutoff.
//
// What keeps the loop on the arithmetic units rather than on shared-memory loads:
// - each thread owns kRows rows, so every tile entry it loads serves kRows pairs;
// - a tile entry is one 16-byte (float) or two 16-byte (double) loads: x, y, z and the species;
// - with one species the pair coefficients live in registers; with several they come from a
//   shared-memory table;
// - without a cutoff the loop calls ljForceOverR directly (what pairForceOverR reduces to then);
// - rows may be listed particles (rowIndex): the collision stage's end-of-step accelerations of the
//   particles about to be resolved; their count read on the device, by a block a row (rowBlocksKernel,
//   which also takes every row at small N);
// - with several GPUs each computes its slice of rows [begin, end) against all n positions, read
//   from its own copy or, with direct access (DA), from the owning GPU's memory (PeerSources);
// - when the rows alone give too few blocks to fill the GPU (N below a few hundred thousand), the
//   j range is split into chunks computed by separate blocks; their partial forces are added by a
//   second kernel in chunk order, so the result does not depend on scheduling (no atomics).
// A full pass over every particle on one GPU evaluates each pair once instead, with Newton's third
// law, where that pays and fits in memory (pairs_once_kernels.cu, pairsOnceApplies below).
#include <algorithm>
#include <stdexcept>

#include "gpu_common.cuh"
#include "gpu_launch.h"
#include "pairs_once.h"

namespace corebox::gpu {
namespace {

constexpr int kRows = 2;
constexpr int64_t kMinChunk = 64;  // sources per chunk at least (a multiple of the warp)

template <class Real>
struct alignas(16) TileEntry {
    Real x, y, z;
    int32_t species;
};

template <class Real, bool kCutoff, bool kMayBeSelf>
__device__ __forceinline__ Real pairForce(const PairCoefficients<Real>& p, Real r2, Real* energy) {
    if (kCutoff) return pairForceOverR(p, r2, energy);
    return ljForceOverR<Real, kMayBeSelf>(p.sigma2, p.eps4, p.mixing, r2, energy);
}

// Adds one staged tile to the thread's rows. kMayBeSelf: the tile holds some of these rows.
template <class Real, bool kEnergy, bool kSingleSpecies, bool kCutoff, bool kMayBeSelf>
__device__ __forceinline__ void accumulateTile(const TileEntry<Real>* tile, int count, const Vec3<Real> (&xi)[kRows],
                                               const int (&si)[kRows], Vec3<Real> (&force)[kRows], double (&energy)[kRows],
                                               const PairCoefficients<Real>& single, const PairCoefficients<Real>* pairs, int s) {
#pragma unroll 4
    for (int k = 0; k < count; ++k) {
        const TileEntry<Real> e = tile[k];
#pragma unroll
        for (int r = 0; r < kRows; ++r) {
            const Vec3<Real> d{xi[r].x - e.x, xi[r].y - e.y, xi[r].z - e.z};
            const Real r2 = norm2(d);
            // Itself (or a coincident centre: no direction): the cutoff path needs the test,
            // ljForceOverR gives zero there by itself.
            if (kCutoff && r2 == Real(0)) continue;
            const PairCoefficients<Real>& p = kSingleSpecies ? single : pairs[si[r] * s + e.species];
            Real u = 0;
            const Real f = pairForce<Real, kCutoff, kMayBeSelf>(p, r2, kEnergy ? &u : nullptr);
            force[r] += f * d;
            if (kEnergy) energy[r] += double(u);
        }
    }
}

// Partial sums of chunk `blockIdx.y` over j in [jBegin, jEnd) for kRows rows per thread; chunk c
// writes force (and energy) partials at c * rows + row when the j range is split, else the result.
template <class Real, bool kEnergy, bool kSingleSpecies, bool kCutoff>
__global__ void __launch_bounds__(kBlock) forceKernel(ForceArgs<Real> a, int64_t chunkLength, Vec3<Real>* partialForce,
                                                       double* partialEnergy) {
    extern __shared__ __align__(16) unsigned char shared[];
    const int s = a.table.count;
    auto* tile = reinterpret_cast<TileEntry<Real>*>(shared);
    auto* pairs = reinterpret_cast<PairCoefficients<Real>*>(tile + blockDim.x);
    if (!kSingleSpecies) {
        for (int k = threadIdx.x; k < s * s; k += blockDim.x) pairs[k] = a.table.pairs[k];
    }
    const PairCoefficients<Real> single = a.table.pairs[0];

    Vec3<Real> xi[kRows], force[kRows];
    int si[kRows];
    double energy[kRows];
    const int64_t blockRowBegin = a.begin + int64_t(blockIdx.x) * blockDim.x * kRows;
    const int64_t blockRowEnd = min(a.end, blockRowBegin + int64_t(blockDim.x) * kRows);
    const int64_t rowBase = blockRowBegin + threadIdx.x;
#pragma unroll
    for (int r = 0; r < kRows; ++r) {
        const int64_t i = rowBase + int64_t(r) * blockDim.x;
        const bool live = i < a.end;
        const int64_t p = live && a.rowIndex ? int64_t(a.rowIndex[i]) : i;  // the row's particle
        xi[r] = live ? a.x[p] : Vec3<Real>{0, 0, 0};
        si[r] = live ? a.species[p] : 0;
        force[r] = Vec3<Real>{0, 0, 0};
        energy[r] = 0;
    }
    const int64_t jBegin = int64_t(blockIdx.y) * chunkLength;
    const int64_t jEnd = min(a.n, jBegin + chunkLength);
    for (int64_t start = jBegin; start < jEnd; start += blockDim.x) {
        __syncthreads();
        const int64_t j = start + threadIdx.x;
        if (j < jEnd) {
            const Vec3<Real> xj = a.peers.count > 0 ? a.peers.x[j / a.peers.chunk][j] : a.x[j];
            tile[threadIdx.x] = TileEntry<Real>{xj.x, xj.y, xj.z, a.species[j]};
        }
        __syncthreads();
        const int count = int(min(int64_t(blockDim.x), jEnd - start));
        if (a.rowIndex || (start < blockRowEnd && start + count > blockRowBegin)) {
            accumulateTile<Real, kEnergy, kSingleSpecies, kCutoff, true>(tile, count, xi, si, force, energy, single, pairs, s);
        } else {
            accumulateTile<Real, kEnergy, kSingleSpecies, kCutoff, false>(tile, count, xi, si, force, energy, single, pairs, s);
        }
    }
#pragma unroll
    for (int r = 0; r < kRows; ++r) {
        const int64_t i = rowBase + int64_t(r) * blockDim.x;
        if (i >= a.end) continue;
        if (partialForce) {
            const int64_t slot = int64_t(blockIdx.y) * (a.end - a.begin) + (i - a.begin);
            partialForce[slot] = force[r];
            if (kEnergy) partialEnergy[slot] = energy[r];
        } else {
            const int64_t out = a.rowIndex ? int64_t(a.rowIndex[i]) : i - a.begin;
            a.acceleration[out] = a.table.invMass[si[r]] * force[r] + a.table.field[si[r]];
            if (kEnergy) a.pairEnergy[out] = energy[r];
        }
    }
}

// Adds the chunk partials of each row in chunk order and finishes the acceleration.
template <class Real>
__global__ void combineChunksKernel(ForceArgs<Real> a, int chunks, const Vec3<Real>* partialForce, const double* partialEnergy) {
    const int64_t row = int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
    const int64_t rows = a.end - a.begin;
    if (row >= rows) return;
    Vec3<Real> force{0, 0, 0};
    double energy = 0;
    for (int c = 0; c < chunks; ++c) {
        force += partialForce[int64_t(c) * rows + row];
        if (partialEnergy) energy += partialEnergy[int64_t(c) * rows + row];
    }
    const int64_t i = a.rowIndex ? int64_t(a.rowIndex[a.begin + row]) : a.begin + row;
    const int64_t out = a.rowIndex ? i : row;
    const int si = a.species[i];
    a.acceleration[out] = a.table.invMass[si] * force + a.table.field[si];
    if (partialEnergy) a.pairEnergy[out] = energy;
}

// A block a row (all pairs, no energy): the block's threads over j in strides, their sums
// added in a fixed order (each warp by shuffles, then the warps in turn). For rows that are few or
// short, where the tiled kernel cannot fill the GPU:
// - listed rows counted on the device (ForceArgs::rowCount): a row's bits depend neither on where its
//   particle stands in the list nor on how many rows there are, so a collision stage whose rounds are
//   queued without their counts being read (runImpactRounds) gives the bits of one that reads each
//   round's count before launching its rows. The rows are few (a round's new impacts: 13 a step at
//   N = 1024, about 600 at 65536), so a block each fills the GPU where the tiled kernel's row blocks
//   would have to be planned from a count the host does not have;
// - every row at small N (kRowBlockMaxRows): at N = 1024 the tiled kernel ran 32 blocks (chunks of j,
//   then a second kernel adding them, 6.1 + 2.9 us on an H200), this one 1024 blocks and no second
//   kernel.
// The rounds' rows are bound by their pair arithmetic, not by reading all n positions per row: at
// N = 65536 (Table 1, several hundred rows in a step's first round) a launch takes about 128 us (ncu,
// H100), some 3e11 to 4e11 pair evaluations a second. Tried and not kept: eight rows a block of 256
// lanes, each position loaded once for the group (the same bits by construction, checked against a
// launch a row): 140 us a launch and the stage 0.602 ms a step against 0.577 (same call, one H100):
// fewer resident warps, no fewer evaluations.
constexpr int kRowBlock = 128;
constexpr int64_t kRowBlockMaxRows = 2048;

template <class Real, bool kSingleSpecies, bool kCutoff>
__global__ void __launch_bounds__(kRowBlock) rowBlocksKernel(ForceArgs<Real> a) {
    __shared__ Vec3<Real> warpSums[kRowBlock / 32];
    const int64_t rows = a.rowCount ? min(a.end - a.begin, int64_t(*a.rowCount)) : a.end - a.begin;
    const int s = a.table.count;
    const int warp = int(threadIdx.x) / 32, lane = int(threadIdx.x) % 32;
    for (int64_t r = blockIdx.x; r < rows; r += gridDim.x) {  // the same trip count for the whole block
        const int64_t i = a.rowIndex ? int64_t(a.rowIndex[a.begin + r]) : a.begin + r;
        const Vec3<Real> xi = a.x[i];
        const int si = a.species[i];
        Vec3<Real> force{0, 0, 0};
        for (int64_t j = threadIdx.x; j < a.n; j += kRowBlock) {
            const Vec3<Real> xj = a.peers.count > 0 ? a.peers.x[j / a.peers.chunk][j] : a.x[j];  // DA: in place
            const Vec3<Real> d{xi.x - xj.x, xi.y - xj.y, xi.z - xj.z};
            const Real r2 = norm2(d);
            if (kCutoff && r2 == Real(0)) continue;  // itself (ljForceOverR gives zero there by itself)
            const PairCoefficients<Real>& p = a.table.pairs[kSingleSpecies ? 0 : si * s + a.species[j]];
            force += pairForce<Real, kCutoff, true>(p, r2, static_cast<Real*>(nullptr)) * d;
        }
        for (int offset = 16; offset > 0; offset /= 2) {
            force.x += __shfl_down_sync(0xffffffffu, force.x, offset);
            force.y += __shfl_down_sync(0xffffffffu, force.y, offset);
            force.z += __shfl_down_sync(0xffffffffu, force.z, offset);
        }
        if (lane == 0) warpSums[warp] = force;
        __syncthreads();
        if (threadIdx.x == 0) {
            Vec3<Real> sum = warpSums[0];
            for (int w = 1; w < kRowBlock / 32; ++w) sum += warpSums[w];
            a.acceleration[a.rowIndex ? i : r] = a.table.invMass[si] * sum + a.table.field[si];
        }
        __syncthreads();  // warpSums read before the next row writes them
    }
}

template <class Real>
void launchRowBlocks(const ForceArgs<Real>& a, cudaStream_t stream) {
    // A block a row up to a few per multiprocessor; more rows than that loop.
    const int64_t rows = a.end - a.begin;
    const unsigned blocks = unsigned(std::min<int64_t>(rows, int64_t(8) * multiprocessorCount()));
    const bool single = a.table.count == 1;
    if (a.hasCutoff) {
        if (single) rowBlocksKernel<Real, true, true><<<blocks, kRowBlock, 0, stream>>>(a);
        else rowBlocksKernel<Real, false, true><<<blocks, kRowBlock, 0, stream>>>(a);
    } else {
        if (single) rowBlocksKernel<Real, true, false><<<blocks, kRowBlock, 0, stream>>>(a);
        else rowBlocksKernel<Real, false, false><<<blocks, kRowBlock, 0, stream>>>(a);
    }
    checkLaunch("row blocks kernel");
}

// Pure hard spheres: each row's acceleration is its species' uniform field, no pair loop.
template <class Real>
__global__ void fieldOnlyKernel(ForceArgs<Real> a) {
    const int64_t i = a.begin + int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
    if (i >= a.end || (a.rowCount && i - a.begin >= int64_t(*a.rowCount))) return;
    const int64_t p = a.rowIndex ? int64_t(a.rowIndex[i]) : i;
    const int64_t out = a.rowIndex ? p : i - a.begin;
    a.acceleration[out] = a.table.field[a.species[p]];
    if (a.pairEnergy) a.pairEnergy[out] = 0;
}

template <class Real, bool kEnergy, bool kSingle>
void launchVariant(const ForceArgs<Real>& a, bool cutoff, dim3 grid, size_t shared, int64_t chunkLength, Vec3<Real>* partialForce,
                   double* partialEnergy, cudaStream_t stream) {
    if (cutoff) forceKernel<Real, kEnergy, kSingle, true><<<grid, kBlock, shared, stream>>>(a, chunkLength, partialForce, partialEnergy);
    else forceKernel<Real, kEnergy, kSingle, false><<<grid, kBlock, shared, stream>>>(a, chunkLength, partialForce, partialEnergy);
}

// How the j range is split: enough blocks for about eight per multiprocessor. A chunk need not be
// whole tiles (the last tile of a chunk is partly filled), so small systems split down to kMinChunk
// sources per chunk: at N = 1024 the rows alone make two blocks, whose threads would each walk all N
// (about 20 us per pass, most of a step at that size).
struct ChunkPlan {
    int64_t chunks, chunkLength;
};

ChunkPlan planChunks(int64_t rows, int64_t n) {
    const int64_t rowBlocks = int64_t(blocksFor(rows, kBlock * kRows));
    const int64_t wanted = int64_t(8) * multiprocessorCount();
    int64_t chunks = std::max<int64_t>(1, (wanted + rowBlocks - 1) / rowBlocks);
    chunks = std::min<int64_t>(chunks, std::max<int64_t>(1, n / kMinChunk));
    const int64_t chunkLength = ((n + chunks - 1) / chunks + kMinChunk - 1) / kMinChunk * kMinChunk;
    return {(n + chunkLength - 1) / chunkLength, chunkLength};
}

template <class Real>
size_t partialForceBytes(int64_t chunks, int64_t rows) {
    return (size_t(chunks) * size_t(rows) * sizeof(Vec3<Real>) + 15) / 16 * 16;
}

}  // namespace

template <class Real>
void launchListForces(const ForceArgs<Real>& a, cudaStream_t stream);  // neighbour_list_kernels.cu

template <class Real>
size_t forceScratchBytes(int64_t rows, int64_t n, bool pairsOnce, int gpus) {
    const ChunkPlan plan = planChunks(rows, n);
    const size_t chunked = plan.chunks <= 1 ? 0 : partialForceBytes<Real>(plan.chunks, rows) + size_t(plan.chunks) * size_t(rows) * sizeof(double);
    const int tile = pairsOnce && (rows == n || gpus > 1) ? pairsOnceTileFor(n, multiprocessorCount(), sizeof(Real), gpus) : 0;
    if (tile == 0) return chunked;
    return std::max(chunked, pairsOnceBytes(n, tile, sizeof(Real), gpus));
}

template <class Real>
bool pairsOnceApplies(const ForceArgs<Real>& a) {
    if (!(a.pairsOnce && a.anyPairForce && a.peers.count == 0 && !a.rowIndex && !a.neighbours && !a.pairEnergy && a.begin == 0 && a.end == a.n))
        return false;
    const int tile = pairsOnceTileFor(a.n, multiprocessorCount(), sizeof(Real));
    return tile > 0 && a.scratchBytes >= pairsOnceBytes(a.n, tile, sizeof(Real), 1);
}

template <class Real>
bool pairsOnceAppliesAcross(const ForceArgs<Real>& a, int gpus) {
    if (!(gpus > 1 && a.pairsOnce && a.anyPairForce && !a.rowIndex && !a.neighbours && !a.pairEnergy)) return false;
    const int tile = pairsOnceTileFor(a.n, multiprocessorCount(), sizeof(Real), gpus);
    return tile > 0 && a.scratchBytes >= pairsOnceBytes(a.n, tile, sizeof(Real), gpus);
}

template <class Real>
int64_t allPairsEvaluations(int64_t n, bool pairsOnce, int gpus) {
    const int tile = pairsOnce ? pairsOnceTileFor(n, multiprocessorCount(), sizeof(Real), gpus) : 0;
    if (tile == 0) return n * (n - 1);
    // Off-diagonal tile pairs evaluate each pair once; a diagonal one every ordered pair and itself.
    int64_t diagonal = 0;
    for (int64_t begin = 0; begin < n; begin += tile) {
        const int64_t m = std::min<int64_t>(tile, n - begin);
        diagonal += m * m;
    }
    return (n * n - diagonal) / 2 + diagonal;
}

template <class Real>
void launchForces(const ForceArgs<Real>& a, cudaStream_t stream) {
    const int64_t rows = a.end - a.begin;
    if (rows <= 0) return;
    if (!a.anyPairForce) {
        fieldOnlyKernel<Real><<<blocksFor(rows), kBlock, 0, stream>>>(a);
        checkLaunch("field kernel");
        return;
    }
    if (a.rowCount && !(a.rowIndex && !a.neighbours && a.peers.count == 0))
        throw std::logic_error("force pass: a row count read on the device needs listed rows and all pairs");
    if (a.rowCount) {
        launchRowBlocks(a, stream);
        return;
    }
    if (a.neighbours && a.peers.count == 0) {
        launchListForces(a, stream);
        return;
    }
    if (pairsOnceApplies(a)) {
        launchPairsOnceForces(a, stream);
        return;
    }
    // With DA too (each row block reads the peers' positions in place): every exchange takes the same
    // pass and gives the same bits, and where every GPU has at most kRowBlockMaxRows rows, several GPUs
    // the bits of one (tests/gpu/test_cuda_conformance.cpp). The price is DA's: every row reads the
    // peers' slices over the link, where the tiled kernel read them once a block of kBlock * kRows rows:
    // bench table1 on two H200s, DA's force passes at N = 4096 0.190 ms a step where the last record, with
    // the tiled kernel, had 0.079 (another host; the step 0.539 against 0.384, NCCL's 0.474 in the same
    // run). Slices of more than kRowBlockMaxRows rows (N above 2048 P) take the tiled kernel either way.
    if (rows <= kRowBlockMaxRows && !a.pairEnergy) {
        launchRowBlocks(a, stream);
        return;
    }
    const bool single = a.table.count == 1;
    const size_t shared = size_t(kBlock) * sizeof(TileEntry<Real>) +
                          (single ? 0 : size_t(a.table.count) * size_t(a.table.count) * sizeof(PairCoefficients<Real>));
    const unsigned rowBlocks = blocksFor(rows, kBlock * kRows);
    const ChunkPlan plan = planChunks(rows, a.n);
    const int64_t chunks = plan.chunks, chunkLength = plan.chunkLength;
    Vec3<Real>* partialForce = nullptr;
    double* partialEnergy = nullptr;
    if (chunks > 1) {
        if (a.scratchBytes < forceScratchBytes<Real>(rows, a.n)) throw std::runtime_error("force pass: scratch buffer too small");
        auto* base = static_cast<unsigned char*>(a.scratch);
        partialForce = reinterpret_cast<Vec3<Real>*>(base);
        if (a.pairEnergy) partialEnergy = reinterpret_cast<double*>(base + partialForceBytes<Real>(chunks, rows));
    }
    const dim3 grid(rowBlocks, unsigned(chunks));
    // The cutoff variant only where one is set; the shifts are all inside pairForceOverR.
    const bool cutoff = a.hasCutoff;
    if (a.pairEnergy) {
        if (single) launchVariant<Real, true, true>(a, cutoff, grid, shared, chunkLength, partialForce, partialEnergy, stream);
        else launchVariant<Real, true, false>(a, cutoff, grid, shared, chunkLength, partialForce, partialEnergy, stream);
    } else {
        if (single) launchVariant<Real, false, true>(a, cutoff, grid, shared, chunkLength, partialForce, partialEnergy, stream);
        else launchVariant<Real, false, false>(a, cutoff, grid, shared, chunkLength, partialForce, partialEnergy, stream);
    }
    checkLaunch("force kernel");
    if (chunks > 1) {
        combineChunksKernel<Real><<<blocksFor(rows), kBlock, 0, stream>>>(a, int(chunks), partialForce, partialEnergy);
        checkLaunch("force combine kernel");
    }
}

namespace {

template <class Real>
__global__ void markMovedKernel(const Vec3<Real>* x, const Vec3<Real>* xBefore, int64_t n, unsigned char* moved, int32_t* movedList,
                                unsigned int* movedCount) {
    const int64_t i = int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
    if (i >= n) return;
    const Vec3<Real> a = x[i], b = xBefore[i];
    const bool m = !(a.x == b.x && a.y == b.y && a.z == b.z);
    moved[i] = m ? 1 : 0;
    if (m) movedList[atomicAdd(movedCount, 1u)] = int32_t(i);
}

template <class Real>
__global__ void exchangeMovedKernel(ForceArgs<Real> a, const Vec3<Real>* xBefore, const unsigned char* moved, const int32_t* movedList,
                                    int64_t movedCount) {
    const int64_t i = int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
    if (i >= a.n || moved[i]) return;
    const Vec3<Real> xi = a.x[i];
    const PairCoefficients<Real>* pairs = a.table.pairs + a.species[i] * a.table.count;
    Vec3<Real> change{0, 0, 0};
    for (int64_t k = 0; k < movedCount; ++k) {
        const int32_t j = movedList[k];
        const PairCoefficients<Real>& p = pairs[a.species[j]];
        const Vec3<Real> now = xi - a.x[j], was = xi - xBefore[j];
        change += pairForceOverR(p, norm2(now), static_cast<Real*>(nullptr)) * now;
        change -= pairForceOverR(p, norm2(was), static_cast<Real*>(nullptr)) * was;
    }
    a.acceleration[i] += a.table.invMass[a.species[i]] * change;
}

}  // namespace

template <class Real>
void launchMarkMoved(const Vec3<Real>* x, const Vec3<Real>* xBefore, int64_t n, unsigned char* moved, int32_t* movedList,
                     unsigned int* movedCount, cudaStream_t stream) {
    cudaMemsetAsync(movedCount, 0, sizeof(unsigned int), stream);
    if (n <= 0) return;
    markMovedKernel<Real><<<blocksFor(n), kBlock, 0, stream>>>(x, xBefore, n, moved, movedList, movedCount);
    checkLaunch("moved particles kernel");
}

template <class Real>
void launchExchangeMovedPairForces(const ForceArgs<Real>& a, const Vec3<Real>* xBefore, const unsigned char* moved, const int32_t* movedList,
                                   int64_t movedCount, cudaStream_t stream) {
    if (a.n <= 0 || movedCount <= 0) return;
    exchangeMovedKernel<Real><<<blocksFor(a.n), kBlock, 0, stream>>>(a, xBefore, moved, movedList, movedCount);
    checkLaunch("moved pair forces kernel");
}

template void launchMarkMoved<float>(const Vec3<float>*, const Vec3<float>*, int64_t, unsigned char*, int32_t*, unsigned int*, cudaStream_t);
template void launchMarkMoved<double>(const Vec3<double>*, const Vec3<double>*, int64_t, unsigned char*, int32_t*, unsigned int*,
                                      cudaStream_t);
template void launchExchangeMovedPairForces<float>(const ForceArgs<float>&, const Vec3<float>*, const unsigned char*, const int32_t*, int64_t,
                                                   cudaStream_t);
template void launchExchangeMovedPairForces<double>(const ForceArgs<double>&, const Vec3<double>*, const unsigned char*, const int32_t*,
                                                    int64_t, cudaStream_t);
template void launchForces<float>(const ForceArgs<float>&, cudaStream_t);
template void launchForces<double>(const ForceArgs<double>&, cudaStream_t);
template size_t forceScratchBytes<float>(int64_t, int64_t, bool, int);
template size_t forceScratchBytes<double>(int64_t, int64_t, bool, int);
template bool pairsOnceApplies<float>(const ForceArgs<float>&);
template bool pairsOnceApplies<double>(const ForceArgs<double>&);
template bool pairsOnceAppliesAcross<float>(const ForceArgs<float>&, int);
template bool pairsOnceAppliesAcross<double>(const ForceArgs<double>&, int);
template int64_t allPairsEvaluations<float>(int64_t, bool, int);
template int64_t allPairsEvaluations<double>(int64_t, bool, int);

}  // namespace corebox::gpu
