// The panel's logic without ImGui: every control's edit reaches the simulation parameter it names;
// live ones at once, restart-needed ones only on Reset. Switching method or precision mid-run keeps
// the state (positions continuous across the switch).
#include <gtest/gtest.h>

#include <cmath>

#include "physics_fixtures.h"
#include "session.h"
#include "live_controls.h"

using namespace corebox;
using namespace corebox::testing;

namespace {

Scene twoSpecies() {
    Scene scene;
    SpeciesDef a, b;
    a.name = "A";
    a.count = 60;
    a.radius = 0.45;
    b.name = "B";
    b.count = 40;
    b.radius = 0.45;
    b.mass = 2;
    scene.species = {a, b};
    scene.box.size = {8, 8, 8};
    scene.interaction.cutoff = 2.5;
    scene.integrator.method = Method::Rk4;
    scene.integrator.dt = 2e-3;
    scene.thermostat.kind = ThermostatKind::Bussi;
    return scene;
}

BackendChoice cpu() { return BackendChoice{"cpu", Precision::Fp64, 1, 0}; }

}  // namespace

TEST(LiveControls, LiveEditsReachTheRunningSimulationWithoutARestart) {
    Session session(twoSpecies(), cpu());
    LiveControls controls(session);
    for (int s = 0; s < 5; ++s) session.simulation().step();
    const ParticleState before = session.simulation().state();
    const uint64_t generation = session.generation();

    controls.setTargetTemperature(2.5);
    controls.setThermostatTau(0.3);
    controls.setThermostatKind(ThermostatKind::Rescale);
    controls.setMixing(0, 1, 0.25);
    controls.setMethod(Method::Verlet);
    controls.setDt(1e-3);
    controls.setRestitution(0.8);
    controls.setWallRestitution(0.7);
    controls.setGravity({0, 0, -0.5});

    const Scene& live = session.runningScene();
    EXPECT_EQ(live.thermostat.temperature, 2.5);
    EXPECT_EQ(live.thermostat.tau, 0.3);
    EXPECT_EQ(live.thermostat.kind, ThermostatKind::Rescale);
    EXPECT_EQ(live.mixing(0, 1), 0.25);
    EXPECT_EQ(live.mixing(1, 0), 0.25);  // symmetric
    EXPECT_EQ(live.mixing(0, 0), 1.0);
    EXPECT_EQ(live.integrator.method, Method::Verlet);
    EXPECT_EQ(live.integrator.dt, 1e-3);
    EXPECT_EQ(live.interaction.restitution, 0.8);
    EXPECT_EQ(live.box.wallRestitution, 0.7);
    EXPECT_EQ(live.interaction.gravity[2], -0.5);
    // No restart: same backend generation, same particles, same step count.
    EXPECT_EQ(session.generation(), generation);
    EXPECT_EQ(session.simulation().stepIndex(), 5);
    const ParticleState after = session.simulation().state();
    for (size_t i = 0; i < before.size(); ++i) ASSERT_EQ(norm2(after.position[i] - before.position[i]), 0.0);
    // And the next step uses them: dt = 1e-3 advances the clock by exactly that.
    const double t = session.simulation().time();
    session.simulation().step();
    EXPECT_NEAR(session.simulation().time() - t, 1e-3, 1e-15);

    controls.setLikeUnlikeMixing(1.2, 0.4);
    EXPECT_EQ(session.runningScene().mixing(0, 0), 1.2);
    EXPECT_EQ(session.runningScene().mixing(1, 1), 1.2);
    EXPECT_EQ(session.runningScene().mixing(0, 1), 0.4);
}

TEST(LiveControls, RestartSettingsWaitForReset) {
    Session session(twoSpecies(), cpu());
    LiveControls controls(session);
    controls.setSpeciesCount(0, 80);
    controls.setSpeciesMass(1, 3.0);
    controls.setSpeciesRadius(0, 0.4);
    controls.setBoxSize({9, 9, 9});
    controls.setSeed(99);
    controls.setTargetTemperature(1.7);  // a live edit in between is kept through the reset
    EXPECT_TRUE(controls.restartPending());
    EXPECT_EQ(session.runningScene().species[0].count, 60);
    EXPECT_EQ(session.runningScene().species[1].mass, 2.0);
    EXPECT_EQ(session.runningScene().box.size[0], 8.0);
    EXPECT_EQ(session.simulation().particleCount(), 100);

    EXPECT_EQ(controls.reset(), "");
    EXPECT_FALSE(controls.restartPending());
    const Scene& live = session.runningScene();
    EXPECT_EQ(live.species[0].count, 80);
    EXPECT_EQ(live.species[1].mass, 3.0);
    EXPECT_EQ(live.species[0].radius, 0.4);
    EXPECT_EQ(live.box.size[0], 9.0);
    EXPECT_EQ(live.init.seed, 99u);
    EXPECT_EQ(live.thermostat.temperature, 1.7);
    EXPECT_EQ(session.simulation().particleCount(), 120);
    EXPECT_EQ(session.simulation().stepIndex(), 0);
}

TEST(LiveControls, AResetThatCannotWorkChangesNothing) {
    Session session(twoSpecies(), cpu());
    LiveControls controls(session);
    controls.setSpeciesCount(0, 100000);  // cannot fit
    const std::string error = controls.reset();
    EXPECT_NE(error.find("more particles than fit"), std::string::npos) << error;
    EXPECT_EQ(session.simulation().particleCount(), 100);
    EXPECT_TRUE(controls.restartPending());
}

TEST(LiveControls, SwitchingMethodOrPrecisionKeepsTheState) {
    Session session(twoSpecies(), cpu());
    LiveControls controls(session);
    for (int s = 0; s < 10; ++s) session.simulation().step();
    const ParticleState before = session.simulation().state();
    controls.setMethod(Method::Hairer10);
    controls.setPrecision(Precision::Fp32);
    EXPECT_EQ(session.simulation().backend().precision(), Precision::Fp32);
    EXPECT_EQ(session.runningScene().integrator.precision, Precision::Fp32);
    const ParticleState after = session.simulation().state();
    for (size_t i = 0; i < before.size(); ++i) {
        // Converted to float: the same positions to float rounding (relative 6e-8 of the box).
        EXPECT_LT(std::sqrt(norm2(after.position[i] - before.position[i])), 8 * 1.2e-7) << i;
    }
    // Continuous across the switch: one more step moves every particle by about v dt, no jump.
    session.simulation().step();
    const ParticleState stepped = session.simulation().state();
    for (size_t i = 0; i < before.size(); ++i) {
        const double moved = std::sqrt(norm2(stepped.position[i] - after.position[i]));
        EXPECT_LT(moved, 20 * 2e-3 * (1 + std::sqrt(norm2(after.velocity[i])))) << i;
    }
    EXPECT_EQ(session.simulation().stepIndex(), 11);
}
