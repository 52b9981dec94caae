// Going on after a blow-up (blow_up_recovery.h). An LJ fluid (the argon preset, thermostat off) run at
// 20 times its dt blows up; each recovery must go back to the last recovery point exactly (the
// restored positions equal those at the point, bit for bit), halve dt, keep the failing run's method,
// and the run must then reach its end with the conserved sum within the blow-up bound. Recovery
// must give up, with the original message, after its attempts at one point are spent.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "blow_up_recovery.h"
#include "errors.h"
#include "physics_fixtures.h"
#include "scene_io.h"

using namespace corebox;
using namespace corebox::testing;

namespace {

Scene argonAtLargeStep(double factor) {
    Scene scene = loadScene(std::string(COREBOX_SOURCE_DIR) + "/assets/argon_gas.toml");
    scene.thermostat.kind = ThermostatKind::None;
    scene.integrator.dt *= factor;
    return scene;
}

BackendMaker makerFor(const std::string& backend) {
    return [backend](const Scene& scene) { return makeTestBackend(backend, scene.integrator.precision); };
}

}  // namespace

class Recovery : public OnEveryBackend {};

TEST_P(Recovery, ABlowUpGoesBackToTheLastGoodStateWithHalfTheStep) {
    const Scene scene = argonAtLargeStep(20);
    const double dt0 = scene.integrator.dt;
    std::unique_ptr<Simulation> sim = makeSimulation(backendName(), scene);
    BlowUpRecovery recovery;
    sim->observe();
    recovery.remember(*sim);
    std::vector<Vec3<double>> pointPositions = sim->state().position;
    int64_t pointStep = 0;
    std::vector<RecoveryEvent> events;
    const int64_t steps = 600, every = 10;
    while (sim->stepIndex() < steps) {
        try {
            sim->step();
            if (sim->stepIndex() % every == 0) {
                sim->observe();
                if (recovery.rememberIfDue(*sim)) {
                    pointPositions = sim->state().position;
                    pointStep = sim->stepIndex();
                }
            }
        } catch (const InstabilityError& e) {
            const double dtBefore = sim->scene().integrator.dt;
            const RecoveryEvent event = recovery.recover(sim, e, makerFor(backendName()));
            events.push_back(event);
            EXPECT_EQ(event.resumedStep, pointStep);
            EXPECT_EQ(sim->stepIndex(), pointStep);
            EXPECT_EQ(event.dtBefore, dtBefore);
            EXPECT_EQ(sim->scene().integrator.dt, 0.5 * dtBefore);
            EXPECT_EQ(sim->scene().integrator.method, scene.integrator.method);
            EXPECT_NE(event.kind, "failed") << event.message;
            const std::vector<Vec3<double>> restored = sim->state().position;
            ASSERT_EQ(restored.size(), pointPositions.size());
            for (size_t i = 0; i < restored.size(); ++i) {
                ASSERT_EQ(restored[i].x, pointPositions[i].x) << "particle " << i;
                ASSERT_EQ(restored[i].y, pointPositions[i].y) << "particle " << i;
                ASSERT_EQ(restored[i].z, pointPositions[i].z) << "particle " << i;
            }
            ASSERT_LE(events.size(), 8u) << "no progress after 8 recoveries";
        }
    }
    ASSERT_FALSE(events.empty()) << "dt = " << dt0 << " did not blow up: the test scene no longer tests recovery";
    EXPECT_LT(sim->scene().integrator.dt, dt0);
    const ObservablesRow end = sim->observe();  // throws if the conserved sum left the bound
    EXPECT_EQ(end.step, steps);
}

TEST_P(Recovery, GivesUpWhenItsAttemptsAtOnePointAreSpent) {
    std::unique_ptr<Simulation> sim = makeSimulation(backendName(), argonAtLargeStep(1));
    BlowUpRecovery recovery(RecoveryPolicy{2, 0});
    const InstabilityError failure("instability at step 3: energy drift beyond the bound: (a test)");
    EXPECT_THROW(recovery.recover(sim, failure, makerFor(backendName())), InstabilityError) << "no point yet";
    sim->observe();
    recovery.remember(*sim);
    const double dt0 = sim->scene().integrator.dt;
    EXPECT_EQ(recovery.recover(sim, failure, makerFor(backendName())).attempt, 1);
    EXPECT_EQ(recovery.recover(sim, failure, makerFor(backendName())).kind, "energy_growth");
    EXPECT_EQ(sim->scene().integrator.dt, 0.25 * dt0);
    try {
        recovery.recover(sim, failure, makerFor(backendName()));
        FAIL() << "a third recovery at one point with 2 attempts allowed";
    } catch (const InstabilityError& e) {
        EXPECT_NE(std::string(e.what()).find("energy drift beyond the bound"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("recovery gave up"), std::string::npos) << e.what();
    }
    // A point taken after progress gives the attempts back.
    sim->step();
    sim->observe();
    EXPECT_TRUE(recovery.rememberIfDue(*sim));
    EXPECT_EQ(recovery.recover(sim, failure, makerFor(backendName())).attempt, 1);
}

INSTANTIATE_TEST_SUITE_P(Backends, Recovery, ::testing::ValuesIn(backendNames()), backendInstanceName);
