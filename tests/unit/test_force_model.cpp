// The automatic choice of pair-force model (force_model.h) and the checks on its settings: each model
// is picked in the cases the rule names, says why, and bad settings are refused or fall back soundly.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "errors.h"
#include "force_model.h"
#include "scene_io.h"
#include "scene_validation.h"

using namespace corebox;

namespace {

// A fluid at rho = 0.8 in a cube, with a cutoff.
StepParameters fluid(int64_t n, double cutoff) {
    StepParameters p;
    SpeciesDef s;
    s.count = n;
    p.species = {s};
    const double l = std::cbrt(double(n) / 0.8);
    p.box.size = {l, l, l};
    p.interaction.cutoff = cutoff;
    return p;
}

bool mentions(const ForceChoice& c, const std::string& word) { return c.reason.find(word) != std::string::npos; }

std::string problemOf(const Scene& scene) {
    try {
        validateScene(scene, SceneLocations("test.toml"));
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

}  // namespace

TEST(ForceModelChoice, NoEpsilonMeansNoPairForce) {
    StepParameters p = fluid(100000, 2.5);
    p.species[0].epsilon = 0;
    const ForceChoice c = chooseForceModel(p, 100000, "cpu");
    EXPECT_EQ(c.model, ForceModel::None);
    EXPECT_TRUE(mentions(c, "epsilon")) << c.reason;
    p.interaction.forces = ForceModel::NeighbourList;  // nothing to sum whatever was asked for
    EXPECT_EQ(chooseForceModel(p, 100000, "cpu").model, ForceModel::None);
}

TEST(ForceModelChoice, NoCutoffMeansAllPairs) {
    const ForceChoice c = chooseForceModel(fluid(100000, 0), 100000, "cpu");
    EXPECT_EQ(c.model, ForceModel::AllPairs);
    EXPECT_TRUE(mentions(c, "no cutoff")) << c.reason;
}

TEST(ForceModelChoice, ACutoffSpanningMostOfTheBoxMeansAllPairs) {
    StepParameters p = fluid(100000, 2.5);
    p.box.size = {6, 6, 6};
    const ForceChoice c = chooseForceModel(p, 100000, "cpu");
    EXPECT_EQ(c.model, ForceModel::AllPairs);
    EXPECT_TRUE(mentions(c, "spans most of the box")) << c.reason;
    // A flat box: the short axis is covered, the long ones are not, so lists still pay.
    p.box.size = {200, 200, 3};
    EXPECT_EQ(chooseForceModel(p, 100000, "cpu").model, ForceModel::NeighbourList);
}

TEST(ForceModelChoice, SmallNMeansAllPairsLargeNMeansLists) {
    for (const std::string backend : {"cpu", "cuda"}) {
        SCOPED_TRACE(backend);
        const int64_t crossover = neighbourListCrossover(backend);
        ASSERT_GT(crossover, 1);
        const ForceChoice below = chooseForceModel(fluid(crossover * 8, 2.5), crossover - 1, backend);
        EXPECT_EQ(below.model, ForceModel::AllPairs);
        EXPECT_TRUE(mentions(below, "crossover")) << below.reason;
        const ForceChoice above = chooseForceModel(fluid(crossover * 8, 2.5), crossover * 8, backend);
        EXPECT_EQ(above.model, ForceModel::NeighbourList);
        EXPECT_NE(above.summary().find("neighbour_list"), std::string::npos) << above.summary();
    }
}

TEST(ForceModelChoice, TheSceneOverridesTheRule) {
    StepParameters p = fluid(100000, 2.5);
    p.interaction.forces = ForceModel::AllPairs;
    EXPECT_EQ(chooseForceModel(p, 100000, "cpu").model, ForceModel::AllPairs);
    p = fluid(50, 2.5);
    p.interaction.forces = ForceModel::NeighbourList;
    EXPECT_EQ(chooseForceModel(p, 50, "cpu").model, ForceModel::NeighbourList);
}

TEST(ForceModelChoice, ListsWithoutACutoffFallBackToAllPairs) {
    StepParameters p = fluid(100000, 0);  // e.g. a live edit of the cutoff to 0
    p.interaction.forces = ForceModel::NeighbourList;
    const ForceChoice c = chooseForceModel(p, 100000, "cpu");
    EXPECT_EQ(c.model, ForceModel::AllPairs);
    EXPECT_TRUE(mentions(c, "no cutoff")) << c.reason;
}

TEST(ForceModelChoice, ACutoffBeyondHalfTheBoxKeepsListsAndSaysSo) {
    StepParameters p = fluid(1000, 6.0);
    p.box.size = {10, 10, 10};
    p.interaction.forces = ForceModel::NeighbourList;
    const ForceChoice c = chooseForceModel(p, 1000, "cpu");
    EXPECT_EQ(c.model, ForceModel::NeighbourList);
    EXPECT_TRUE(mentions(c, "half the smallest box edge")) << c.reason;
}

TEST(ForceModelSettings, ZeroSkinAndListsWithoutCutoffAreRefused) {
    Scene scene;
    SpeciesDef s;
    s.count = 20;
    scene.species = {s};
    scene.interaction.cutoff = 2.5;
    EXPECT_EQ(problemOf(scene), "");
    scene.interaction.skin = 0;
    EXPECT_NE(problemOf(scene).find("interaction.skin"), std::string::npos) << problemOf(scene);
    scene.interaction.skin = -0.1;
    EXPECT_NE(problemOf(scene).find("interaction.skin"), std::string::npos);
    scene.interaction.skin = 0.3;
    scene.interaction.cutoff = 0;
    scene.interaction.forces = ForceModel::NeighbourList;
    EXPECT_NE(problemOf(scene).find("needs a cutoff"), std::string::npos) << problemOf(scene);
}

TEST(ForceModelChoice, ABackendWithoutListsRunsAllPairsAndSaysSo) {
    const ForceChoice c = chooseForceModel(fluid(100000, 2.5), 100000, "cuda", false);
    EXPECT_EQ(c.model, ForceModel::AllPairs);
    EXPECT_TRUE(mentions(c, "no neighbour lists")) << c.reason;
}

// The presets made for cut-off forces load, validate and run on lists wherever lists exist.
TEST(ForceModelPresets, CoexistenceAndDemixingRunOnNeighbourLists) {
    for (const char* name : {"lj_coexistence", "binary_demixing"}) {
        SCOPED_TRACE(name);
        const Scene scene = loadScene(std::string(COREBOX_SOURCE_DIR) + "/assets/" + name + ".toml");
        EXPECT_EQ(problemOf(scene), "");
        EXPECT_GT(scene.interaction.cutoff, 0);
        for (const std::string backend : {"cpu", "cuda"}) {
            const ForceChoice c = chooseForceModel(stepParametersOf(scene), scene.particleCount(), backend);
            EXPECT_EQ(c.model, ForceModel::NeighbourList) << backend << ": " << c.reason;
        }
    }
}
