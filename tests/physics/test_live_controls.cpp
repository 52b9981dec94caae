// The panel's logic without ImGui: every control's edit reaches what the running simulation computes
// with; live ones at once, restart-needed ones only on Reset. Switching method or precision mid-run
// keeps the state (positions continuous across the switch).
//
// The live edits are checked by behaviour that only holds if the backend uses the new values, never
// by reading back the scene copy the controls keep (that copy is read only for the controls' own
// bookkeeping: symmetric mixing, like/unlike, what a reset applies): gravity changes the momentum of
// a free system by M g dt per step; restitution turns exactly-zero dissipation into positive; mixing
// changes the potential energy by the amount the pair potential gives for the new x_ij; and after all
// edits at once the run steps exactly like a simulation created with those values. Every test runs on
// each backend present (cpu, cuda).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "physics_fixtures.h"
#include "session.h"
#include "live_controls.h"
#include "thermostat_formulas.h"

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

Vec3<double> momentumOf(const ParticleState& st, const Scene& scene) {
    Vec3<double> p{0, 0, 0};
    for (size_t i = 0; i < st.size(); ++i) p += scene.species[size_t(st.species[i])].mass * st.velocity[i];
    return p;
}

double totalMassOf(const ParticleState& st, const Scene& scene) {
    double m = 0;
    for (int32_t s : st.species) m += scene.species[size_t(s)].mass;
    return m;
}

// dU/dx_ij summed over the pairs of species i and j (i != j) of a state, for LJ with sigma = eps = 1
// and a shifted-force cutoff r_c. The potential is linear in the mixing: only the attraction
// -4 x g(R), g = R^-6, carries it, shifted like the rest, so per pair within r_c
//     dU/dx = -4 [g(R) - g(r_c) + 6 (R - r_c) g(r_c) / r_c]
// and a mixing edit x -> x' changes the potential by (x' - x) times this sum. Also returns the sum of
// |dU/dx| over those pairs (the scale for round-off).
double mixingDerivative(const ParticleState& st, int32_t si, int32_t sj, double rc, double* magnitude) {
    const double grc = std::pow(rc, -6.0);
    double sum = 0, abs = 0;
    for (size_t i = 0; i < st.size(); ++i) {
        for (size_t k = i + 1; k < st.size(); ++k) {
            const bool pair =
                (st.species[i] == si && st.species[k] == sj) || (st.species[i] == sj && st.species[k] == si);
            if (!pair) continue;
            const double r = std::sqrt(norm2(st.position[i] - st.position[k]));
            if (r >= rc) continue;
            const double d = -4.0 * (std::pow(r, -6.0) - grc + 6.0 * (r - rc) * grc / rc);
            sum += d;
            abs += std::fabs(d);
        }
    }
    *magnitude = abs;
    return sum;
}

double maxDifference(const ParticleState& a, const ParticleState& b) {
    double worst = 0;
    for (size_t i = 0; i < a.size(); ++i) {
        for (int k = 0; k < 3; ++k) {
            worst = std::max(worst, std::fabs(a.position[i][k] - b.position[i][k]));
            worst = std::max(worst, std::fabs(a.velocity[i][k] - b.velocity[i][k]));
        }
    }
    return worst;
}

class LiveEdits : public OnEveryBackend {
protected:
    BackendChoice choice() const { return BackendChoice{backendName(), Precision::Fp64, 1, 0}; }
};

}  // namespace

INSTANTIATE_TEST_SUITE_P(Backends, LiveEdits, ::testing::ValuesIn(backendNames()), backendInstanceName);

TEST_P(LiveEdits, LiveEditsReachTheRunningSimulationWithoutARestart) {
    Session session(twoSpecies(), choice());
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

    // The controls' own bookkeeping: one mixing edit sets x_01 and x_10 and leaves the diagonal.
    const Scene& live = session.runningScene();
    EXPECT_EQ(live.mixing(0, 1), 0.25);
    EXPECT_EQ(live.mixing(1, 0), 0.25);
    EXPECT_EQ(live.mixing(0, 0), 1.0);
    // No restart: same backend generation, same particles, same step count.
    EXPECT_EQ(session.generation(), generation);
    EXPECT_EQ(session.simulation().stepIndex(), 5);
    const ParticleState after = session.simulation().state();
    for (size_t i = 0; i < before.size(); ++i) ASSERT_EQ(norm2(after.position[i] - before.position[i]), 0.0);

    // What the next steps compute with. A simulation created with the edited values (written out
    // here, not taken from the controls) from the same state on the same backend does the same
    // arithmetic, so the two must agree to round-off (they agree bitwise on the CPU; 1e-12 leaves room
    // for a reduction order that a GPU may vary between runs). The smallest effect of a single edit
    // that was lost on its way to the backend is ~3e-8 in three steps (the method: rk4 instead of
    // verlet), so 1e-12 tells them apart; one created with the values before the edits must not agree.
    Scene edited = twoSpecies();
    edited.thermostat.kind = ThermostatKind::Rescale;
    edited.thermostat.temperature = 2.5;
    edited.thermostat.tau = 0.3;
    edited.interaction.mixing = {{1.0, 0.25}, {0.25, 1.0}};
    edited.integrator.method = Method::Verlet;
    edited.integrator.dt = 1e-3;
    edited.interaction.restitution = 0.8;
    edited.box.wallRestitution = 0.7;
    edited.interaction.gravity = {0, 0, -0.5};
    auto reference = makeSimulation(backendName(), edited, before, 1);
    auto unedited = makeSimulation(backendName(), twoSpecies(), before, 1);

    Simulation& sim = session.simulation();
    const double t0 = sim.time();
    for (int s = 0; s < 3; ++s) {
        const double thermostat0 = sim.thermostatEnergy();
        sim.step();
        reference->step();
        unedited->step();
        // The rescale thermostat with the new target and tau: K' = K + (dt / tau) (K_target - K), K the
        // kinetic energy before it acted (K' minus the energy it added). Bussi, or the old target or
        // tau, give another K'.
        const double kAfter = sim.lastKineticEnergy();
        const double kBefore = kAfter - (sim.thermostatEnergy() - thermostat0);
        const double kTarget = 0.5 * 3.0 * double(sim.particleCount()) * 2.5;
        EXPECT_NEAR(kAfter, rescaleKineticEnergy(kBefore, kTarget, 1e-3, 0.3), 1e-12 * kAfter) << "step " << s;
    }
    // dt = 1e-3 advances the clock by exactly that per step.
    EXPECT_NEAR(sim.time() - t0, 3e-3, 1e-15);
    const ParticleState now = sim.state();
    EXPECT_LT(maxDifference(now, reference->state()), 1e-12);
    EXPECT_GT(maxDifference(now, unedited->state()), 1e-8);

    controls.setLikeUnlikeMixing(1.2, 0.4);
    EXPECT_EQ(session.runningScene().mixing(0, 0), 1.2);
    EXPECT_EQ(session.runningScene().mixing(1, 1), 1.2);
    EXPECT_EQ(session.runningScene().mixing(0, 1), 0.4);
}

TEST_P(LiveEdits, GravityEditChangesTheMomentumByMGDtPerStep) {
    // A free system: hard spheres without pair force, on a lattice of spacing 5 in a 20^3 box (2.5
    // from the walls), at T = 1: in a few steps of 1e-3 nothing collides, so only gravity can change
    // the momentum, by M g dt per step exactly. Tolerance 1e-9 of M g dt: the momentum sums over 64
    // particles carry round-off ~1e-14, the effect checked is the whole M g dt.
    Scene scene = hardSphereScene(0, 20.0, Method::Verlet, 1e-3);
    SpeciesDef light = scene.species[0], heavy = scene.species[0];
    light.name = "light";
    light.count = 40;
    heavy.name = "heavy";
    heavy.count = 24;
    heavy.mass = 2.5;
    scene.species = {light, heavy};
    Session session(scene, choice());
    LiveControls controls(session);
    Simulation& sim = session.simulation();
    const double mass = totalMassOf(sim.state(), scene);
    auto checkSteps = [&](const std::array<double, 3>& g) {
        for (int s = 0; s < 3; ++s) {
            const Vec3<double> p0 = momentumOf(sim.state(), scene);
            const StepReport r = sim.step();
            ASSERT_EQ(r.pairCollisions + r.wallCollisions + r.contacts, 0) << "the system is not free";
            const Vec3<double> dp = momentumOf(sim.state(), scene) - p0;
            const double scale = std::max(mass * std::sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]) * 1e-3, 1e-3);
            for (int a = 0; a < 3; ++a) {
                EXPECT_NEAR(dp[a], mass * g[size_t(a)] * 1e-3, 1e-9 * scale)
                    << "g = (" << g[0] << ", " << g[1] << ", " << g[2] << "), step " << s << ", axis " << a;
            }
        }
    };
    checkSteps({0, 0, 0});
    controls.setGravity({0.3, 0, -0.5});
    checkSteps({0.3, 0, -0.5});
    controls.setGravity({0, 0, 0});
    checkSteps({0, 0, 0});
}

TEST_P(LiveEdits, AGravityEditIsWorkDoneNotDrift) {
    // 300 hard spheres at T = 1 with no gravity, then g = 50 switched on: the potential energy of the
    // same state moves by sum m g z ~ 300 x 50 x 4, a hundred times the energy scale (the drift bound
    // is half of it). The edit is work done on the system: the run goes on, the conserved sum keeps
    // its value across the edit up to that work, and afterwards moves only by integration error.
    Scene scene = hardSphereScene(300, 8.0, Method::Verlet, 1e-3);
    Session session(scene, choice());
    LiveControls controls(session);
    Simulation& sim = session.simulation();
    for (int s = 0; s < 5; ++s) sim.step();
    const double scale = sim.energyScale();
    const double before = sim.observe().conserved();
    controls.setGravity({0, 0, -50});
    const double work = sim.parameterWork();
    EXPECT_GT(std::fabs(work), 50 * scale) << "the edit should move the potential far beyond the drift bound";
    ObservablesRow row;
    ASSERT_NO_THROW(row = sim.observe());
    EXPECT_NEAR(row.conserved(), before + work, 1e-9 * std::fabs(work));
    for (int s = 0; s < 50; ++s) ASSERT_NO_THROW(sim.step());
    ASSERT_NO_THROW(row = sim.observe());
    EXPECT_LT(std::fabs(row.conserved() - (before + work)), 1e-3 * std::fabs(work));
    // Switching it off again is work too (of the state the spheres have fallen to).
    const double beforeOff = row.conserved(), workOn = sim.parameterWork();
    controls.setGravity({0, 0, 0});
    ASSERT_NO_THROW(row = sim.observe());
    EXPECT_NEAR(row.conserved(), beforeOff + (sim.parameterWork() - workOn), 1e-9 * std::fabs(work));
}

TEST_P(LiveEdits, RestitutionEditsChangeTheDissipatedEnergy) {
    // A dense elastic hard-sphere gas (packing fraction 0.31, T = 2): many pair and wall collisions in
    // every phase of 40 steps. Elastic collisions dissipate exactly nothing ((1 - e^2) = 0, no forces),
    // so any dissipation in a phase comes from the one restitution that was edited below 1.
    Scene scene = hardSphereScene(300, 8.0, Method::Verlet, 5e-3);
    scene.init.temperature = 2.0;
    Session session(scene, choice());
    LiveControls controls(session);
    Simulation& sim = session.simulation();
    struct Phase {
        int64_t pair = 0, wall = 0;
        double dissipated = 0;
    };
    auto run = [&]() {
        Phase p;
        for (int s = 0; s < 40; ++s) {
            const StepReport r = sim.step();
            p.pair += r.pairCollisions;
            p.wall += r.wallCollisions;
            p.dissipated += r.dissipated;
        }
        return p;
    };
    const Phase elastic = run();
    EXPECT_GT(elastic.pair, 20);
    EXPECT_GT(elastic.wall, 20);
    EXPECT_EQ(elastic.dissipated, 0.0);

    controls.setWallRestitution(0.7);  // pairs stay elastic: only wall hits can dissipate
    const Phase walls = run();
    EXPECT_GT(walls.wall, 20);
    // Each wall hit loses (1 - 0.49) m v_n^2 / 2, about 0.5 kT on average: far above zero.
    EXPECT_GT(walls.dissipated, 0.05 * double(walls.wall));

    controls.setWallRestitution(1.0);
    controls.setRestitution(0.8);  // walls elastic again: only pair collisions can dissipate
    const Phase pairs = run();
    EXPECT_GT(pairs.pair, 20);
    EXPECT_GT(pairs.dissipated, 0.05 * double(pairs.pair));

    controls.setRestitution(1.0);  // and back: exactly nothing again
    EXPECT_EQ(run().dissipated, 0.0);
}

TEST_P(LiveEdits, MixingEditChangesThePotentialByThePairAmount) {
    Session session(twoSpecies(), choice());
    LiveControls controls(session);
    Simulation& sim = session.simulation();
    for (int s = 0; s < 5; ++s) sim.step();
    const ParticleState st = sim.state();
    const double rc = twoSpecies().interaction.cutoff;
    double scale01 = 0, scale00 = 0, scale11 = 0;
    const double d01 = mixingDerivative(st, 0, 1, rc, &scale01);
    const double d00 = mixingDerivative(st, 0, 0, rc, &scale00);
    const double d11 = mixingDerivative(st, 1, 1, rc, &scale11);
    ASSERT_GT(std::fabs(d01), 1.0);  // enough unlike pairs within the cutoff for the edit to show
    ASSERT_GT(std::fabs(d00) + std::fabs(d11), 1.0);

    // No step in between: the state is the same, so the potential (a force pass on the backend) moves
    // only by the mixing. Tolerance: 1e-10 of the summed |dU/dx| (round-off of sums of ~1e3 terms).
    const double u0 = sim.observe().potential;
    controls.setMixing(0, 1, 0.25);
    const double u1 = sim.observe().potential;
    EXPECT_NEAR(u1 - u0, (0.25 - 1.0) * d01, 1e-10 * scale01);

    controls.setLikeUnlikeMixing(1.2, 0.4);
    const double u2 = sim.observe().potential;
    EXPECT_NEAR(u2 - u0, (0.4 - 1.0) * d01 + (1.2 - 1.0) * (d00 + d11), 1e-10 * (scale01 + scale00 + scale11));
    // The controls' bookkeeping of the like/unlike edit.
    EXPECT_EQ(session.runningScene().mixing(0, 0), 1.2);
    EXPECT_EQ(session.runningScene().mixing(1, 1), 1.2);
    EXPECT_EQ(session.runningScene().mixing(0, 1), 0.4);
    EXPECT_EQ(session.runningScene().mixing(1, 0), 0.4);
}

TEST_P(LiveEdits, RestartSettingsWaitForReset) {
    Session session(twoSpecies(), choice());
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
    EXPECT_EQ(session.simulation().state().size(), 100u);

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
    // The backend holds the new particles: 80 of species 0 and 40 of species 1.
    const ParticleState st = session.simulation().state();
    ASSERT_EQ(st.size(), 120u);
    EXPECT_EQ(std::count(st.species.begin(), st.species.end(), 0), 80);
}

TEST_P(LiveEdits, AResetThatCannotWorkChangesNothing) {
    Session session(twoSpecies(), choice());
    LiveControls controls(session);
    controls.setSpeciesCount(0, 100000);  // cannot fit
    const std::string error = controls.reset();
    EXPECT_NE(error.find("more particles than fit"), std::string::npos) << error;
    EXPECT_EQ(session.simulation().particleCount(), 100);
    EXPECT_EQ(session.simulation().state().size(), 100u);
    EXPECT_TRUE(controls.restartPending());
}

TEST_P(LiveEdits, SwitchingMethodOrPrecisionKeepsTheState) {
    Session session(twoSpecies(), choice());
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

TEST_P(LiveEdits, ValuesTheSceneRulesRefuseChangeNothing) {
    // The values a scene file may not hold are refused live too, with the rule's message, and the run
    // steps exactly as one that never saw them.
    Session edited(twoSpecies(), choice()), untouched(twoSpecies(), choice());
    LiveControls controls(edited);
    const double nan = std::nan("");
    const std::vector<std::pair<std::string, std::string>> refusals{
        {controls.setDt(-1), "integrator.dt"},
        {controls.setDt(nan), "integrator.dt"},
        {controls.setTargetTemperature(-5), "thermostat.temperature"},
        {controls.setThermostatTau(0), "thermostat.tau"},
        {controls.setMixing(0, 1, -1), "interaction.mixing"},
        {controls.setMixing(0, 7, 1), "out of range"},
        {controls.setLikeUnlikeMixing(1, nan), "interaction.mixing"},
        {controls.setRestitution(1.5), "interaction.restitution"},
        {controls.setWallRestitution(-0.1), "box.wall_restitution"},
        {controls.setGravity({nan, 0, 0}), "interaction.gravity"},
        {controls.setGravity({1e308, 0, 0}), "interaction.gravity"},
        {controls.setSpeciesMass(0, -1), "species.mass"},
        {controls.setSpeciesRadius(1, std::numeric_limits<double>::infinity()), "species.radius"},
        {controls.setBoxSize({8, 0, 8}), "box.size"},
    };
    for (const auto& [message, key] : refusals) {
        EXPECT_NE(message.find(key), std::string::npos) << "expected a refusal naming " << key << ", got: '" << message << "'";
    }
    EXPECT_FALSE(controls.lastRefusal().empty());
    EXPECT_FALSE(controls.restartPending());
    for (int s = 0; s < 20; ++s) {
        edited.simulation().step();
        untouched.simulation().step();
    }
    EXPECT_EQ(maxDifference(edited.simulation().state(), untouched.simulation().state()), 0.0);
    // A good value after refusals is applied, and clears the refusal.
    EXPECT_EQ(controls.setDt(1e-3), "");
    EXPECT_TRUE(controls.lastRefusal().empty());
    EXPECT_EQ(edited.runningScene().integrator.dt, 1e-3);
}
