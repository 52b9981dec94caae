// All-pairs forces with Newton's third law on one GPU or several: each pair of particles is evaluated
// once and its force given to both, half the arithmetic of the ordered-pair kernel (force_kernels.cu).
//
// Design note. Why not the obvious schemes:
// - atomics on the partner's force (float or double) make the sum depend on scheduling: results
//   would differ run to run, and restarts and CPU/GPU comparisons would lose their meaning;
// - a warp reduction of the partner's force for every column costs more shuffles than the pair it
//   saves (15 shuffles and adds per column per warp, against ~20 instructions for 32 pairs).
// What this kernel does instead (rotation within a warp):
// - a block of kWarps warps takes a pair of tiles (I, J), I <= J, of kTile = 256 kWarps particles
//   each (kWarps 1, 2 or 4: the largest tile whose pairs fill the GPU, pairs_once.h). Each lane
//   holds kLaneRows rows of tile I in registers (its own forces fi too) and one column of the
//   current group of 32 columns of tile J with that column's running force fj. At each of 32 steps
//   every lane evaluates its rows against its column, adds f to its rows and -f to the column, then
//   takes the next lane's column and fj (6 shuffles per kLaneRows pairs). After 32 steps each lane
//   holds its own column again with fj summed over the warp's rows: every pair once, in a fixed
//   order, no atomics.
// - the warps of a block have different rows and the same columns, so a group's fj are summed over
//   the warps in shared memory (warp order) and written once per tile pair.
// - every (tile X, partner tile Y) pair has one slot of partial forces: fi of pair (I, J) goes to
//   slot (I, J), fj to slot (J, I), a diagonal pair (I, I) computes its tile against itself without
//   the third law (self pairs give zero) into slot (I, I). A second kernel adds each row's slots in
//   partner order and finishes the acceleration. Same bits on every run.
// - rows and columns past n are placed so far away that their forces underflow to exactly zero.
// Cost per pair evaluated: the ordered kernel's ~17 instructions plus 3 fused multiply-adds for the
// partner and 6/kLaneRows shuffles, for two ordered pairs. The slots take tiles^2 x kTile forces of
// memory (50 MB at N = 65536 in fp32 with 1024-particle tiles), so the kernel is used only below a
// memory budget, and only where the tile pairs fill the GPU (pairsOnceTileFor); elsewhere the ordered
// kernel runs. Energies (observables) use the ordered kernel.
// Several GPUs (launchPairsOnceShare, launchPairsOnceCombine): the tile pairs are numbered and each GPU
// evaluates an equal run of them (pairs_once.h) into its own slots, which are never copied: each GPU
// first adds, for every particle, the slots it wrote in partner-tile order (a full-length array of row
// sums, 12 bytes a particle in fp32), then, after a barrier, each GPU adds the GPUs' row sums of its
// own slice in GPU order, reading the peers' arrays in place (peer access). Why not move the slots to
// the rows' owners: at N = 65536 on two GPUs that is 25 MB a pass over NVLink (~75 us at the 335 GB/s
// a peer read reached in `bench p2p`) against 0.4 MB of row sums. The sums differ from one GPU's only
// in rounding (another tile, another grouping), and are the same bits run to run and for every
// exchange method, which all deliver the same positions; with DA the kernel reads the peers'
// positions in place, as the ordered kernel does. Measured on an H200
// (`corebox bench forces`, one LJ species): fp32 2.39e12 pair interactions/s at N = 65536 and 2.59e12
// at 262144 (the ordered kernel: 1.55e12 and 1.58e12), fp64 1.10e12 and 1.17e12 (0.69e12, 0.70e12).
#include "gpu_common.cuh"
#include "gpu_launch.h"
#include "pairs_once.h"

namespace corebox::gpu {
namespace {

constexpr int kLaneRows = kPairsOnceWarpRows / 32;
constexpr unsigned kFullMask = 0xffffffffu;

// Where the padding rows and columns sit: far enough that r^-8 underflows to zero in this precision,
// near enough that r^2 stays finite.
template <class Real>
__device__ __forceinline__ Real farAway();
template <>
__device__ __forceinline__ float farAway<float>() { return 1e18f; }
template <>
__device__ __forceinline__ double farAway<double>() { return 1e100; }

template <class Real>
__device__ __forceinline__ Vec3<Real> positionOrFar(const ForceArgs<Real>& a, int64_t j) {
    if (j >= a.n) return Vec3<Real>{farAway<Real>(), farAway<Real>(), farAway<Real>()};
    return a.peers.count > 0 ? a.peers.x[j / a.peers.chunk][j] : a.x[j];
}

// F/R of one pair. kMayBeSelf: the diagonal tile pair meets each particle against itself (R = 0).
template <class Real, bool kCutoff, bool kMayBeSelf>
__device__ __forceinline__ Real pairOnce(const PairCoefficients<Real>& p, Real r2) {
    if (kCutoff) return (kMayBeSelf && r2 == Real(0)) ? Real(0) : pairForceOverR(p, r2, static_cast<Real*>(nullptr));
    return ljForceOverR<Real, kMayBeSelf>(p.sigma2, p.eps4, p.mixing, r2, static_cast<Real*>(nullptr));
}

template <class Real>
__device__ __forceinline__ Vec3<Real> shuffleFromNext(Vec3<Real> v, int next) {
    return Vec3<Real>{__shfl_sync(kFullMask, v.x, next), __shfl_sync(kFullMask, v.y, next), __shfl_sync(kFullMask, v.z, next)};
}

// Rows of tile I (in registers) against the columns of tile J, 32 at a time. kThirdLaw: also sums the
// columns' forces and writes them to slot (J, I); the diagonal pair (I, I) runs without it.
template <class Real, int kWarps, bool kSingle, bool kCutoff, bool kThirdLaw>
__device__ __forceinline__ void sweepColumns(const ForceArgs<Real>& a, int64_t I, int64_t J, int64_t tiles, const Vec3<Real> (&xi)[kLaneRows],
                                             const int (&si)[kLaneRows], Vec3<Real> (&fi)[kLaneRows], const PairCoefficients<Real>& single,
                                             const PairCoefficients<Real>* pairs, Vec3<Real> (*columnSums)[kWarps][32], Vec3<Real>* partial) {
    constexpr int kTile = kWarps * kPairsOnceWarpRows;
    const int warp = int(threadIdx.x) / 32, lane = int(threadIdx.x) % 32;
    const int next = (lane + 1) & 31;
    const int s = a.table.count;
    for (int g = 0; g < kTile / 32; ++g) {
        const int64_t j = J * kTile + g * 32 + lane;
        Vec3<Real> xj = positionOrFar(a, j);
        int sj = (!kSingle && j < a.n) ? a.species[j] : 0;
        Vec3<Real> fj{0, 0, 0};
        // Step k: this lane holds column (lane + k) mod 32.
#pragma unroll 2
        for (int k = 0; k < 32; ++k) {
#pragma unroll
            for (int r = 0; r < kLaneRows; ++r) {
                const Vec3<Real> d{xi[r].x - xj.x, xi[r].y - xj.y, xi[r].z - xj.z};
                const PairCoefficients<Real>& p = kSingle ? single : pairs[si[r] * s + sj];
                const Real f = pairOnce<Real, kCutoff, !kThirdLaw>(p, norm2(d));
                fi[r] += f * d;
                if (kThirdLaw) fj -= f * d;
            }
            xj = shuffleFromNext(xj, next);
            if (!kSingle) sj = __shfl_sync(kFullMask, sj, next);
            if (kThirdLaw) fj = shuffleFromNext(fj, next);
        }
        if (kThirdLaw && kWarps == 1) {
            if (j < a.n) partial[(J * tiles + I) * kTile + g * 32 + lane] = fj;
        } else if (kThirdLaw) {
            // Back at its own column: add the warps' sums in warp order (two buffers: one barrier a group).
            columnSums[g & 1][warp][lane] = fj;
            __syncthreads();
            if (warp == 0 && j < a.n) {
                Vec3<Real> sum = columnSums[g & 1][0][lane];
#pragma unroll
                for (int w = 1; w < kWarps; ++w) sum += columnSums[g & 1][w][lane];
                partial[(J * tiles + I) * kTile + g * 32 + lane] = sum;
            }
        }
    }
}

template <class Real, int kWarps, bool kSingle, bool kCutoff>
__global__ void __launch_bounds__(32 * kWarps)
    pairsOnceKernel(ForceArgs<Real> a, int64_t tiles, int64_t firstItem, Vec3<Real>* partial) {
    constexpr int kTile = kWarps * kPairsOnceWarpRows;
    // One block an item of this GPU's share: the upper triangle (the lower one is its third law).
    int64_t I, J;
    pairsOnceTilePair(firstItem + int64_t(blockIdx.x), tiles, I, J);
    extern __shared__ __align__(16) unsigned char shared[];
    auto* columnSums = reinterpret_cast<Vec3<Real>(*)[kWarps][32]>(shared);
    auto* pairs = reinterpret_cast<PairCoefficients<Real>*>(shared + 2 * sizeof(Vec3<Real>) * kWarps * 32);
    if (!kSingle) {
        for (int k = int(threadIdx.x); k < a.table.count * a.table.count; k += 32 * kWarps) pairs[k] = a.table.pairs[k];
        __syncthreads();
    }
    const PairCoefficients<Real> single = a.table.pairs[0];
    const int warp = int(threadIdx.x) / 32, lane = int(threadIdx.x) % 32;
    const int64_t rowBase = I * kTile + warp * kPairsOnceWarpRows + lane;
    Vec3<Real> xi[kLaneRows], fi[kLaneRows];
    int si[kLaneRows];
#pragma unroll
    for (int r = 0; r < kLaneRows; ++r) {
        const int64_t i = rowBase + 32 * r;
        xi[r] = positionOrFar(a, i);
        si[r] = (!kSingle && i < a.n) ? a.species[i] : 0;
        fi[r] = Vec3<Real>{0, 0, 0};
    }
    if (I == J) sweepColumns<Real, kWarps, kSingle, kCutoff, false>(a, I, J, tiles, xi, si, fi, single, pairs, columnSums, partial);
    else sweepColumns<Real, kWarps, kSingle, kCutoff, true>(a, I, J, tiles, xi, si, fi, single, pairs, columnSums, partial);
#pragma unroll
    for (int r = 0; r < kLaneRows; ++r) {
        const int64_t i = rowBase + 32 * r;
        if (i < a.n) partial[(I * tiles + J) * kTile + (i - I * kTile)] = fi[r];
    }
}

// Each row's slots in partner-tile order, then the acceleration.
template <class Real>
__global__ void combinePairsOnceKernel(ForceArgs<Real> a, int tile, int64_t tiles, const Vec3<Real>* partial) {
    const int64_t i = int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
    if (i >= a.n) return;
    const int64_t X = i / tile, local = i % tile;
    Vec3<Real> force{0, 0, 0};
    for (int64_t Y = 0; Y < tiles; ++Y) force += partial[(X * tiles + Y) * tile + local];
    const int s = a.species[i];
    a.acceleration[i] = a.table.invMass[s] * force + a.table.field[s];
}

// Several GPUs: every particle's slots that this GPU's share [firstItem, endItem) wrote, in
// partner-tile order (slot (X, Y) was written by the item of (min(X, Y), max(X, Y))).
template <class Real>
__global__ void sumShareKernel(int64_t n, int tile, int64_t tiles, int64_t firstItem, int64_t endItem, const Vec3<Real>* partial,
                               Vec3<Real>* rowSums) {
    const int64_t i = int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
    if (i >= n) return;
    const int64_t X = i / tile, local = i % tile;
    Vec3<Real> force{0, 0, 0};
    for (int64_t Y = 0; Y < tiles; ++Y) {
        const int64_t item = Y < X ? pairsOnceItem(Y, X, tiles) : pairsOnceItem(X, Y, tiles);
        if (item >= firstItem && item < endItem) force += partial[(X * tiles + Y) * tile + local];
    }
    rowSums[i] = force;
}

// Several GPUs: the rows of this GPU's slice, the GPUs' row sums in GPU order, then the acceleration.
template <class Real>
__global__ void combineSharesKernel(ForceArgs<Real> a, PairsOnceSums<Real> sums) {
    const int64_t i = a.begin + int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
    if (i >= a.end) return;
    Vec3<Real> force{0, 0, 0};
    for (int g = 0; g < sums.count; ++g) force += sums.rows[g][i];
    const int s = a.species[i];
    a.acceleration[i - a.begin] = a.table.invMass[s] * force + a.table.field[s];
}

template <class Real, int kWarps>
void launchTiles(const ForceArgs<Real>& a, int64_t tiles, int64_t firstItem, int64_t endItem, Vec3<Real>* partial, cudaStream_t stream) {
    if (endItem <= firstItem) return;
    const bool single = a.table.count == 1;
    const size_t shared = 2 * sizeof(Vec3<Real>) * kWarps * 32 +
                          (single ? 0 : size_t(a.table.count) * size_t(a.table.count) * sizeof(PairCoefficients<Real>));
    const unsigned grid = unsigned(endItem - firstItem);
    constexpr int threads = 32 * kWarps;
    if (single) {
        if (a.hasCutoff) pairsOnceKernel<Real, kWarps, true, true><<<grid, threads, shared, stream>>>(a, tiles, firstItem, partial);
        else pairsOnceKernel<Real, kWarps, true, false><<<grid, threads, shared, stream>>>(a, tiles, firstItem, partial);
    } else {
        if (a.hasCutoff) pairsOnceKernel<Real, kWarps, false, true><<<grid, threads, shared, stream>>>(a, tiles, firstItem, partial);
        else pairsOnceKernel<Real, kWarps, false, false><<<grid, threads, shared, stream>>>(a, tiles, firstItem, partial);
    }
}

// The tile of a pass over n particles shared by `gpus` GPUs, checked against the scratch it needs
// (the slots, and with several GPUs the row sums after them).
template <class Real>
int checkedTile(const ForceArgs<Real>& a, int gpus) {
    const int tile = pairsOnceTileFor(a.n, multiprocessorCount(), sizeof(Real), gpus);
    if (tile == 0 || a.scratchBytes < pairsOnceBytes(a.n, tile, sizeof(Real), gpus))
        throw std::runtime_error("pairs-once force pass: not applicable or scratch buffer too small");
    return tile;
}

// The tile pairs [firstItem, endItem) into the slots at the start of the scratch.
template <class Real>
void launchTilePairs(const ForceArgs<Real>& a, int tile, int64_t firstItem, int64_t endItem, cudaStream_t stream) {
    const int64_t tiles = pairsOnceTiles(a.n, tile);
    auto* partial = static_cast<Vec3<Real>*>(a.scratch);
    if (tile == 4 * kPairsOnceWarpRows) launchTiles<Real, 4>(a, tiles, firstItem, endItem, partial, stream);
    else if (tile == 2 * kPairsOnceWarpRows) launchTiles<Real, 2>(a, tiles, firstItem, endItem, partial, stream);
    else launchTiles<Real, 1>(a, tiles, firstItem, endItem, partial, stream);
    checkLaunch("pairs-once force kernel");
}

}  // namespace

template <class Real>
void launchPairsOnceForces(const ForceArgs<Real>& a, cudaStream_t stream) {
    const int tile = checkedTile(a, 1);
    const int64_t tiles = pairsOnceTiles(a.n, tile);
    launchTilePairs(a, tile, 0, pairsOnceItems(tiles), stream);
    combinePairsOnceKernel<Real><<<blocksFor(a.n), kBlock, 0, stream>>>(a, tile, tiles, static_cast<const Vec3<Real>*>(a.scratch));
    checkLaunch("pairs-once combine kernel");
}

template <class Real>
Vec3<Real>* pairsOnceRowSums(const ForceArgs<Real>& a, int gpus) {
    const int tile = checkedTile(a, gpus);
    return reinterpret_cast<Vec3<Real>*>(static_cast<unsigned char*>(a.scratch) + pairsOnceScratchBytes(a.n, tile, sizeof(Real)));
}

template <class Real>
void launchPairsOnceShare(const ForceArgs<Real>& a, int gpu, int gpus, cudaStream_t stream) {
    const int tile = checkedTile(a, gpus);
    const int64_t tiles = pairsOnceTiles(a.n, tile);
    const int64_t first = pairsOnceFirstItem(gpu, gpus, tiles), end = pairsOnceFirstItem(gpu + 1, gpus, tiles);
    launchTilePairs(a, tile, first, end, stream);
    sumShareKernel<Real><<<blocksFor(a.n), kBlock, 0, stream>>>(a.n, tile, tiles, first, end, static_cast<const Vec3<Real>*>(a.scratch),
                                                                 pairsOnceRowSums(a, gpus));
    checkLaunch("pairs-once share sum kernel");
}

template <class Real>
void launchPairsOnceCombine(const ForceArgs<Real>& a, const PairsOnceSums<Real>& sums, cudaStream_t stream) {
    const int64_t rows = a.end - a.begin;
    if (rows <= 0) return;
    combineSharesKernel<Real><<<blocksFor(rows), kBlock, 0, stream>>>(a, sums);
    checkLaunch("pairs-once combine kernel");
}

template void launchPairsOnceForces<float>(const ForceArgs<float>&, cudaStream_t);
template void launchPairsOnceForces<double>(const ForceArgs<double>&, cudaStream_t);
template Vec3<float>* pairsOnceRowSums<float>(const ForceArgs<float>&, int);
template Vec3<double>* pairsOnceRowSums<double>(const ForceArgs<double>&, int);
template void launchPairsOnceShare<float>(const ForceArgs<float>&, int, int, cudaStream_t);
template void launchPairsOnceShare<double>(const ForceArgs<double>&, int, int, cudaStream_t);
template void launchPairsOnceCombine<float>(const ForceArgs<float>&, const PairsOnceSums<float>&, cudaStream_t);
template void launchPairsOnceCombine<double>(const ForceArgs<double>&, const PairsOnceSums<double>&, cudaStream_t);

}  // namespace corebox::gpu
