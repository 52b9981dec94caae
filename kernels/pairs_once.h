// Geometry of the pairs-once force pass (kernels/pairs_once_kernels.cu: all pairs on one GPU or
// several with Newton's third law), shared by its launch and the host side that sizes its scratch.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>

#include "hd.h"

namespace corebox::gpu {

constexpr int kPairsOnceWarpRows = 256;  // rows a warp holds (8 a lane); a tile is 1, 2 or 4 warps of rows
// The most memory the partial forces may take; above it (N beyond about 400,000 in fp32) the ordered
// kernel runs, whose scratch grows as N, not N^2.
constexpr size_t kPairsOnceScratchBudget = size_t(2) << 30;
// Tile pairs per multiprocessor the pass needs to keep every one busy to the end (measured on an
// H200: with about 4 per multiprocessor the pass ran at half its rate, the last wave mostly idle; on
// two H200s at N = 65536, 6 instead of 12, so 1024-particle tiles at 7.9 a multiprocessor instead of
// 512 at 15.6, gave 4.14e12 pair interactions/s instead of 4.31e12: `bench forces --gpus 2`).
constexpr int64_t kPairsOnceItemsPerMultiprocessor = 12;

inline int64_t pairsOnceTiles(int64_t n, int tile) { return (n + tile - 1) / tile; }

// One slot of `tile` forces (3 reals) per ordered pair of tiles.
inline size_t pairsOnceScratchBytes(int64_t n, int tile, size_t realBytes) {
    const size_t tiles = size_t(pairsOnceTiles(n, tile));
    return tiles * tiles * size_t(tile) * 3 * realBytes;
}

// The scratch a pass needs: the slots, and when `gpus` GPUs share it each GPU's sums of its slots
// per particle (3 reals a particle) after them (pairsOnceRowSums).
inline size_t pairsOnceBytes(int64_t n, int tile, size_t realBytes, int gpus) {
    return pairsOnceScratchBytes(n, tile, realBytes) + (gpus > 1 ? size_t(n) * 3 * realBytes : 0);
}

// The tile for n particles on `gpus` GPUs of `multiprocessors` each: the largest (fewest partial sums)
// whose tile pairs fill every GPU with its share, 0 when none does (small n: the ordered kernel's
// chunks fill it better) or when the partial forces would pass the memory budget.
inline int pairsOnceTileFor(int64_t n, int multiprocessors, size_t realBytes, int gpus = 1) {
    for (int tile = 4 * kPairsOnceWarpRows; tile >= kPairsOnceWarpRows; tile /= 2) {
        const int64_t tiles = pairsOnceTiles(n, tile);
        if (tiles * (tiles + 1) / 2 < kPairsOnceItemsPerMultiprocessor * multiprocessors * gpus) continue;
        return pairsOnceScratchBytes(n, tile, realBytes) <= kPairsOnceScratchBudget ? tile : 0;
    }
    return 0;
}

// Several GPUs share the tile pairs (I, J), I <= J, numbered row by row: item(I, J) = I tiles -
// I (I - 1) / 2 + J - I. GPU g of `gpus` evaluates the items [first(g), first(g + 1)): equal shares,
// whose rows and columns lie anywhere (every GPU holds every position before a force pass).
inline int64_t pairsOnceItems(int64_t tiles) { return tiles * (tiles + 1) / 2; }
inline int64_t pairsOnceFirstItem(int gpu, int gpus, int64_t tiles) { return pairsOnceItems(tiles) * gpu / gpus; }
COREBOX_HD inline int64_t pairsOnceItem(int64_t I, int64_t J, int64_t tiles) { return I * tiles - I * (I - 1) / 2 + (J - I); }
// The tile pair (I, J) of an item: I is the largest row whose first item is <= item, from the root of
// I^2 - (2 tiles + 1) I + 2 item = 0, then corrected by one where the root rounded across a row.
COREBOX_HD inline void pairsOnceTilePair(int64_t item, int64_t tiles, int64_t& I, int64_t& J) {
    const double b = 2.0 * double(tiles) + 1.0;
    I = int64_t((b - sqrt(b * b - 8.0 * double(item))) / 2.0);
    if (I > 0 && pairsOnceItem(I, I, tiles) > item) --I;
    if (I + 1 < tiles && pairsOnceItem(I + 1, I + 1, tiles) <= item) ++I;
    J = I + (item - pairsOnceItem(I, I, tiles));
}

}  // namespace corebox::gpu
