// Geometry of the pairs-once force pass (kernels/pairs_once_kernels.cu: all pairs on one GPU with
// Newton's third law), shared by its launch and the host side that sizes its scratch memory.
#pragma once

#include <cstddef>
#include <cstdint>

namespace corebox::gpu {

constexpr int kPairsOnceWarpRows = 256;  // rows a warp holds (8 a lane); a tile is 1, 2 or 4 warps of rows
// The most memory the partial forces may take; above it (N beyond about 400,000 in fp32) the ordered
// kernel runs, whose scratch grows as N, not N^2.
constexpr size_t kPairsOnceScratchBudget = size_t(2) << 30;
// Tile pairs per multiprocessor the pass needs to keep every one busy to the end (measured on an
// H200: with about 4 per multiprocessor the pass ran at half its rate, the last wave mostly idle).
constexpr int64_t kPairsOnceItemsPerMultiprocessor = 12;

inline int64_t pairsOnceTiles(int64_t n, int tile) { return (n + tile - 1) / tile; }

// One slot of `tile` forces (3 reals) per ordered pair of tiles.
inline size_t pairsOnceScratchBytes(int64_t n, int tile, size_t realBytes) {
    const size_t tiles = size_t(pairsOnceTiles(n, tile));
    return tiles * tiles * size_t(tile) * 3 * realBytes;
}

// The tile for n particles on a GPU of `multiprocessors`: the largest (fewest partial sums) whose tile
// pairs fill the GPU, 0 when none does (small n: the ordered kernel's chunks fill it better) or when
// the partial forces would pass the memory budget.
inline int pairsOnceTileFor(int64_t n, int multiprocessors, size_t realBytes) {
    for (int tile = 4 * kPairsOnceWarpRows; tile >= kPairsOnceWarpRows; tile /= 2) {
        const int64_t tiles = pairsOnceTiles(n, tile);
        if (tiles * (tiles + 1) / 2 < kPairsOnceItemsPerMultiprocessor * multiprocessors) continue;
        return pairsOnceScratchBytes(n, tile, realBytes) <= kPairsOnceScratchBudget ? tile : 0;
    }
    return 0;
}

}  // namespace corebox::gpu
