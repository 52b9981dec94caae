// The numbering of the pairs-once pass's tile pairs (kernels/pairs_once.h), which the GPUs sharing a
// pass split into runs: every item maps to its tile pair and back, row by row in the upper triangle,
// and the GPUs' runs cover every item exactly once, in equal shares. Host arithmetic only (no GPU).
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdlib>

#include "pairs_once.h"

using namespace corebox::gpu;

TEST(PairsOnceShares, EveryItemIsItsTilePairAndBack) {
    for (int64_t tiles : {1, 2, 3, 17, 64, 128, 257, 400}) {
        int64_t item = 0;
        for (int64_t I = 0; I < tiles; ++I) {
            for (int64_t J = I; J < tiles; ++J, ++item) {
                ASSERT_EQ(pairsOnceItem(I, J, tiles), item) << tiles << " tiles, pair " << I << ", " << J;
                int64_t i = -1, j = -1;
                pairsOnceTilePair(item, tiles, i, j);
                ASSERT_EQ(i, I) << tiles << " tiles, item " << item;
                ASSERT_EQ(j, J) << tiles << " tiles, item " << item;
            }
        }
        EXPECT_EQ(item, pairsOnceItems(tiles)) << tiles << " tiles";
    }
}

TEST(PairsOnceShares, TheGpusRunsCoverEveryItemOnceInEqualShares) {
    for (int64_t tiles : {64, 129, 256}) {
        for (int gpus : {1, 2, 3, 4, 8}) {
            EXPECT_EQ(pairsOnceFirstItem(0, gpus, tiles), 0);
            EXPECT_EQ(pairsOnceFirstItem(gpus, gpus, tiles), pairsOnceItems(tiles));
            for (int g = 0; g < gpus; ++g) {
                const int64_t share = pairsOnceFirstItem(g + 1, gpus, tiles) - pairsOnceFirstItem(g, gpus, tiles);
                EXPECT_LE(std::abs(share * gpus - pairsOnceItems(tiles)), gpus) << tiles << " tiles, GPU " << g << " of " << gpus;
            }
        }
    }
}

// The tile of a shared pass gives every GPU enough tile pairs to fill it (pairsOnceTileFor).
TEST(PairsOnceShares, TheTileFillsEveryGpuWithItsShare) {
    constexpr int kMultiprocessors = 132;  // an H100 or H200
    for (int gpus : {1, 2, 4}) {
        for (int64_t n : {20000, 40037, 65536, 262144}) {
            const int tile = pairsOnceTileFor(n, kMultiprocessors, sizeof(float), gpus);
            if (tile == 0) continue;
            const int64_t share = pairsOnceItems(pairsOnceTiles(n, tile)) / gpus;
            EXPECT_GE(share, kPairsOnceItemsPerMultiprocessor * kMultiprocessors) << n << " particles on " << gpus << " GPUs";
        }
    }
    EXPECT_EQ(pairsOnceTileFor(65536, kMultiprocessors, sizeof(float), 1), 1024);
    EXPECT_EQ(pairsOnceTileFor(65536, kMultiprocessors, sizeof(float), 2), 512);
    EXPECT_EQ(pairsOnceTileFor(4099, kMultiprocessors, sizeof(float), 2), 0);  // too few pairs: the ordered kernel
}
