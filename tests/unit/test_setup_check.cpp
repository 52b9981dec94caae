// The set-up's overlap check runs on every hardware thread: it must still report the overlap a check
// in index order meets first, and the progress callback must hear of every stage up to its end.
#include <gtest/gtest.h>

#include <map>
#include <string>

#include "errors.h"
#include "initial_conditions.h"

using namespace corebox;

namespace {

// n spheres of radius 0.4 on a line of spacing 1 along x in a long box: no overlaps.
Scene lineScene(int64_t n) {
    Scene scene;
    SpeciesDef s;
    s.count = n;
    s.radius = 0.4;
    s.epsilon = 0;
    scene.species = {s};
    scene.box.size = {double(n), 1, 1};
    return scene;
}

ParticleState lineState(int64_t n) {
    ParticleState state;
    state.resize(size_t(n));
    for (int64_t i = 0; i < n; ++i) state.position[size_t(i)] = {double(i) + 0.5, 0.5, 0.5};
    return state;
}

std::string overlapMessage(const Scene& scene, const ParticleState& state) {
    try {
        checkPlacement(scene, state, "test");
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

}  // namespace

TEST(SetupCheck, ReportsTheFirstOverlapInIndexOrderWhateverTheThreads) {
    // 100000 particles: many blocks of the check, spread over the threads. Two overlaps, one late in
    // the index order and one early; the early one is what a check in file order meets first.
    const int64_t n = 100000;
    const Scene scene = lineScene(n);
    ParticleState state = lineState(n);
    EXPECT_EQ(overlapMessage(scene, state), "");
    state.position[90001].x = state.position[90000].x + 0.5;  // pair (90000, 90001) at 0.5 < 0.8
    state.position[12346].x = state.position[12345].x + 0.3;  // pair (12345, 12346) at 0.3 < 0.8
    const std::string message = overlapMessage(scene, state);
    EXPECT_NE(message.find("particles 12345 and 12346 overlap: centre distance 0.3"), std::string::npos) << message;
}

TEST(SetupCheck, ProgressReachesTheEndOfEveryStage) {
    Scene scene = lineScene(200000);
    scene.init.placement = Placement::Lattice;
    std::map<std::string, std::pair<int64_t, int64_t>> last;  // stage -> (done, total) of its last call
    bool monotonic = true;
    const ParticleState state = makeInitialState(scene, [&](const char* stage, int64_t done, int64_t total) {
        auto found = last.find(stage);
        if (found != last.end() && done < found->second.first) monotonic = false;
        last[stage] = {done, total};
    });
    EXPECT_EQ(int64_t(state.size()), 200000);
    EXPECT_TRUE(monotonic);
    ASSERT_EQ(last.count("lattice placement"), 1u);
    ASSERT_EQ(last.count("overlap check"), 1u);
    EXPECT_EQ(last["lattice placement"].first, last["lattice placement"].second);
    EXPECT_EQ(last["overlap check"].first, 200000);
}

TEST(SetupCheck, AcceptsTheResidualOverlapsOfARestingPileAndRefusesDeeperOnes) {
    // A saved resting pile holds contacts a little closer than a_i + a_j and balls a little past the
    // wall plane (the contact phase's residual): it must read back. Beyond 1%, the file is wrong.
    const Scene scene = lineScene(4);
    ParticleState state = lineState(4);
    state.position[1].x = state.position[0].x + 0.8 * (1 - 0.5 * kRestingOverlapAccepted);
    state.position[0].x = 0.4 * (1 - 0.5 * kRestingOverlapAccepted);
    EXPECT_EQ(overlapMessage(scene, state), "");
    state.position[3].x = state.position[2].x + 0.8 * (1 - 2 * kRestingOverlapAccepted);
    EXPECT_NE(overlapMessage(scene, state).find("particles 2 and 3 overlap"), std::string::npos);
    state = lineState(4);
    state.position[0].x = 0.4 * (1 - 2 * kRestingOverlapAccepted);
    EXPECT_NE(overlapMessage(scene, state).find("particle 0 lies outside the box"), std::string::npos);
}
