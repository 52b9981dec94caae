// method = "auto" (auto_integrator.h) on the argon preset made small (125 LJ particles at its density,
// thermostat off, on the CPU): a loose energy tolerance must pick a run with fewer force passes per unit time than a tight
// one, and each chosen run, continued for twice the pilot's time, must keep its energy error per unit
// time within the tolerance.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "auto_integrator.h"
#include "errors.h"
#include "initial_conditions.h"
#include "physics_fixtures.h"
#include "scene_io.h"
#include "study_runs.h"
#include "vocabulary.h"

using namespace corebox;
using namespace corebox::testing;

namespace {

Scene argonAuto(double tolerance) {
    Scene scene = loadScene(std::string(COREBOX_SOURCE_DIR) + "/assets/argon_gas.toml");
    scene.thermostat.kind = ThermostatKind::None;
    const double side = scene.box.size[0] * std::cbrt(125.0 / double(scene.species[0].count));
    scene.species[0].count = 125;
    scene.box.size = {side, side, side};
    scene.integrator.automatic = true;
    scene.integrator.tolerance = tolerance;
    return scene;
}

// The energy error per unit time of the chosen integrator over `time`.
double errorPerTime(const Scene& scene, const IntegratorDef& chosen, double time) {
    Scene run = scene;
    run.integrator = chosen;
    auto sim = makeSimulation("cpu", run);
    const double e0 = sim->observe().conserved();
    double worst = 0;
    for (int k = 1; k <= 20; ++k) {
        advanceTo(*sim, time * k / 20.0);
        worst = std::max(worst, std::fabs(sim->observe().conserved() - e0) / sim->energyScale());
    }
    return worst / time;
}

}  // namespace

TEST(AutoIntegrator, ALooseToleranceIsCheaperAndEachChoiceMeetsItsTolerance) {
    AutoIntegratorOptions options;
    options.backend = "cpu";
    options.budgetSeconds = 600;  // a loaded machine slows the pilot, not its outcome
    const double loose = 1e-3, tight = 1e-5;  // 1e-6 is near this scene's floor (the cutoff)
    const Scene looseScene = argonAuto(loose), tightScene = argonAuto(tight);
    const AutoIntegratorChoice a = chooseIntegrator(looseScene, makeInitialState(looseScene), options);
    const AutoIntegratorChoice b = chooseIntegrator(tightScene, makeInitialState(tightScene), options);
    for (const AutoIntegratorChoice* c : {&a, &b}) {
        for (const PilotTrial& t : c->trials)
            std::printf("  tol %g: %s %s dt %g: %.3g per unit time, %.4g passes, %.3g s per unit time, %s\n", c->tolerance,
                        methodName(t.method), precisionName(t.precision), t.dt, t.errorPerTime, t.forcePassesPerTime,
                        t.wallSecondsPerTime, t.outcome.c_str());
        std::printf("%s\n", c->summary.c_str());
        ASSERT_TRUE(c->met) << c->summary;
        EXPECT_FALSE(c->integrator.automatic);
    }
    EXPECT_LT(a.chosen.forcePassesPerTime, b.chosen.forcePassesPerTime) << a.summary << "\n" << b.summary;
    const double pilotTime = 500 * looseScene.integrator.dt;
    EXPECT_LE(errorPerTime(looseScene, a.integrator, 2 * pilotTime), loose);
    EXPECT_LE(errorPerTime(tightScene, b.integrator, 2 * pilotTime), tight);
}

TEST(AutoIntegrator, ASceneWithoutPairForcesGetsVerletWithoutAPilot) {
    Scene scene = hardSphereScene(200, 20, Method::Rk4, 2e-3);
    scene.integrator.automatic = true;
    const AutoIntegratorChoice c = chooseIntegrator(scene, makeInitialState(scene), AutoIntegratorOptions{"cpu", 0, 0, 20});
    EXPECT_FALSE(c.piloted);
    EXPECT_EQ(c.integrator.method, Method::Verlet);
    EXPECT_EQ(c.integrator.dt, 2e-3);
    EXPECT_TRUE(c.trials.empty());
}

TEST(AutoIntegrator, ASimulationRefusesAnUnresolvedScene) {
    Scene scene = argonAuto(1e-4);
    EXPECT_THROW(makeSimulation("cpu", scene), InputError);
}
