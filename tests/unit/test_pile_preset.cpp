// The ball pile of `corebox bench pile`: every benchmark size fits its box (bench_scenes.h), and the
// measures both engines are judged by (pile_measures.h) say what they claim. That assets/pile.toml is
// the benchmark's scene is checked with the other presets (test_scene_io.cpp).
#include <gtest/gtest.h>

#include <vector>

#include "bench_scenes.h"
#include "packing.h"
#include "pile_measures.h"

using namespace corebox;

TEST(PilePreset, EveryBenchmarkSizeFitsItsBox) {
    for (int64_t n : {200, 2000, 10000, 40000}) {
        EXPECT_EQ(pileBox(n), kPile.box) << n;
    }
    EXPECT_EQ(pileBox(100000)[0], 47.5);  // 30 sqrt(2.5) = 47.43, up to a tenth
    EXPECT_EQ(pileBox(1000000)[0], 150.0);
    for (int64_t n : {2000, 10000, 40000, 100000, 1000000, 4000000}) {
        const Scene scene = pileScene(n, Precision::Fp32);
        EXPECT_EQ(scene.box.size[0], scene.box.size[1]) << n;
        EXPECT_EQ(scene.box.size[2], 60.0) << n;
        EXPECT_FALSE(packingProblem(scene).has_value()) << n << ": " << packingProblem(scene)->message;
    }
}

TEST(PileMeasures, OverlapWallPenetrationAndEscapes) {
    const std::array<double, 3> box{10, 10, 10};
    // Two balls 0.9 apart (10% of a diameter), one 0.45 from the floor (5%), one outside.
    const std::vector<Vec3<double>> x{{5, 5, 5}, {5.9, 5, 5}, {2, 2, 0.45}, {2, 2, 10.2}, {8, 8, 8}};
    const PileStateMeasures m = measurePileState(x, 0.5, box);
    EXPECT_NEAR(m.maxOverlap, 0.1, 1e-12);
    EXPECT_NEAR(m.maxWallPenetration, 0.7, 1e-12);  // the escaped ball is 0.7 diameters past its limit
    EXPECT_EQ(m.outside, 1);
    EXPECT_EQ(m.nonFinite, 0);
    const PileStateMeasures apart = measurePileState({{5, 5, 5}, {6, 5, 5}}, 0.5, box);
    EXPECT_EQ(apart.maxOverlap, 0.0);  // touching is not overlapping
    EXPECT_EQ(apart.maxWallPenetration, 0.0);
}

TEST(PileMeasures, TimeToRestIsWhenTheKineticEnergyStaysLow) {
    // U falls by 100; K spikes, drops under 1 at t = 2, rises again at t = 3, and stays low from t = 4.
    const std::vector<PileEnergySample> samples{{0, 0, 100}, {1, 50, 50}, {2, 0.5, 0},
                                                {3, 5, 0},   {4, 0.9, 0}, {5, 0.1, 0}};
    ASSERT_TRUE(pileTimeToRest(samples).has_value());
    EXPECT_EQ(*pileTimeToRest(samples), 4.0);
    std::vector<PileEnergySample> moving = samples;
    moving.push_back({6, 2, 0});
    EXPECT_FALSE(pileTimeToRest(moving).has_value());
    EXPECT_FALSE(pileTimeToRest({{0, 0, 100}}).has_value());  // nothing released yet: not at rest
}

TEST(PileMeasures, FrameTimes) {
    PileFrameTimes t;
    EXPECT_EQ(t.mean(), 0.0);
    t.ms = {1, 2, 3, 6};
    EXPECT_EQ(t.mean(), 3.0);
    EXPECT_EQ(t.meanOfLast(2), 4.5);
    EXPECT_EQ(t.meanOfLast(60), 3.0);
}
