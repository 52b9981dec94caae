// Non-finite values reaching the state must end a run as an instability (InstabilityError, exit code
// 3), never as a crash: a NaN or infinite position goes through the contact grid (kernels/cell_list.h
// clamps it to a valid cell), the collision rounds and the health check. Validation keeps such values
// out of scenes (test_scene_limits.cpp); here they are injected the ways that bypass it: a live
// parameter change (gravity NaN or infinite, dt infinite or 1e308), a scene built in code with a mass
// fp32 cannot invert, and a state with NaN and infinite positions. Run under the ASan preset this is
// also the check that nothing is written out of bounds. LJ species, so NaNs travel through forces too.
#include <gtest/gtest.h>

#include <limits>
#include <string>
#include <vector>

#include "errors.h"
#include "physics_fixtures.h"

using namespace corebox;
using namespace corebox::testing;

namespace {

class NonFiniteState : public OnEveryBackend {};
INSTANTIATE_TEST_SUITE_P(Backends, NonFiniteState, ::testing::ValuesIn(backendNames()), backendInstanceName);

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

Scene ljGas(Precision precision) {
    Scene scene = hardSphereScene(64, 10.0);
    scene.species[0].epsilon = 1.0;
    scene.integrator.precision = precision;
    return scene;
}

// Steps until the simulation throws; fails the test when it never does or throws anything else.
void expectInstabilityWithin(Simulation& sim, int steps, const std::string& what) {
    for (int k = 0; k < steps; ++k) {
        try {
            sim.step();
        } catch (const InstabilityError&) {
            return;
        }
    }
    ADD_FAILURE() << what << ": no InstabilityError in " << steps << " steps";
}

}  // namespace

TEST_P(NonFiniteState, LiveParameterChangesThatBreakTheStateEndInAnInstability) {
    for (Precision precision : {Precision::Fp64, Precision::Fp32}) {
        struct Case {
            const char* what;
            void (*apply)(StepParameters&);
        };
        const Case cases[] = {
            {"gravity NaN", [](StepParameters& p) { p.interaction.gravity = {kNaN, kNaN, kNaN}; }},
            {"gravity inf", [](StepParameters& p) { p.interaction.gravity = {0, 0, -kInf}; }},
            {"dt inf", [](StepParameters& p) { p.integrator.dt = kInf; }},
            {"dt 1e308", [](StepParameters& p) { p.integrator.dt = 1e308; }},
        };
        for (const Case& c : cases) {
            SCOPED_TRACE(std::string(c.what) + (precision == Precision::Fp32 ? " fp32" : " fp64"));
            const Scene scene = ljGas(precision);
            auto sim = makeSimulation(backendName(), scene);
            sim->step();
            StepParameters p = stepParametersOf(sim->scene());
            c.apply(p);
            sim->setStepParameters(p);
            expectInstabilityWithin(*sim, 5, c.what);
        }
    }
}

TEST_P(NonFiniteState, AMassFp32CannotInvertEndsInAnInstability) {
    Scene scene = ljGas(Precision::Fp32);
    scene.species[0].mass = 1e-40;  // below fp32's normal range: 1/m is infinite
    auto sim = makeSimulation(backendName(), scene);
    expectInstabilityWithin(*sim, 5, "mass 1e-40 in fp32");
}

TEST_P(NonFiniteState, NaNAndInfinitePositionsInTheStateEndInAnInstability) {
    const Scene scene = ljGas(Precision::Fp64);
    auto sim = makeSimulation(backendName(), scene);
    ParticleState broken = sim->state();
    broken.position[0] = {kNaN, kNaN, kNaN};
    broken.position[7] = {kInf, -kInf, 5.0};
    broken.position[20] = {1e300, 5.0, -1e300};
    sim->backend().setState(broken);
    expectInstabilityWithin(*sim, 3, "NaN and infinite positions");
}
