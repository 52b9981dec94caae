// Convergence order of every integrator in fp64 on a bound, rotating and vibrating LJ pair with a
// shifted-force cutoff (smooth, no collisions). The error at t = 1.2 against a Hairer-10 reference
// at a tiny step is fitted against dt on a log-log scale; step sizes keep the error well above
// round-off (> 1e-11) and in the asymptotic range.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "lj_pair.h"

using namespace corebox;
using namespace corebox::testing;

namespace {

constexpr double kEndTime = 1.2;

ParticleState runPair(Method method, double dt) {
    Scene scene = ljPairScene(method, dt);
    auto sim = makeSimulation(scene, ljPairState(1.25, 0.3, 0.6));
    const int steps = int(std::lround(kEndTime / dt));
    for (int s = 0; s < steps; ++s) sim->step();
    return sim->state();
}

double errorAgainst(const ParticleState& a, const ParticleState& ref) {
    double e = 0;
    for (size_t i = 0; i < a.size(); ++i) {
        e = std::max(e, std::sqrt(norm2(a.position[i] - ref.position[i])));
        e = std::max(e, std::sqrt(norm2(a.velocity[i] - ref.velocity[i])) * 0.1);
    }
    return e;
}

// Least-squares slope of log(error) against log(dt).
double fittedOrder(Method method, const std::vector<double>& steps, const ParticleState& reference) {
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    for (double dt : steps) {
        const double e = errorAgainst(runPair(method, dt), reference);
        EXPECT_GT(e, 1e-11) << methodName(method) << " dt " << dt << ": error at round-off, slope meaningless";
        ::testing::Test::RecordProperty(std::string(methodName(method)) + "_dt_" + std::to_string(dt), std::to_string(e));
        const double x = std::log(dt), y = std::log(e);
        sx += x;
        sy += y;
        sxx += x * x;
        sxy += x * y;
    }
    const double n = double(steps.size());
    return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

class Convergence : public ::testing::Test {
protected:
    static void SetUpTestSuite() { s_reference = new ParticleState(runPair(Method::Hairer10, kEndTime / 600)); }
    static void TearDownTestSuite() { delete s_reference; }
    static ParticleState* s_reference;
};
ParticleState* Convergence::s_reference = nullptr;

}  // namespace

TEST_F(Convergence, EulerIsFirstOrder) {
    EXPECT_NEAR(fittedOrder(Method::Euler, {1.2e-3, 6e-4, 3e-4}, *s_reference), 1.0, 0.3);
}
TEST_F(Convergence, Rk2IsSecondOrder) { EXPECT_NEAR(fittedOrder(Method::Rk2, {6e-3, 3e-3, 1.5e-3}, *s_reference), 2.0, 0.3); }
TEST_F(Convergence, VerletIsSecondOrder) { EXPECT_NEAR(fittedOrder(Method::Verlet, {6e-3, 3e-3, 1.5e-3}, *s_reference), 2.0, 0.3); }
TEST_F(Convergence, Rk4IsFourthOrder) { EXPECT_NEAR(fittedOrder(Method::Rk4, {1.2e-2, 6e-3, 3e-3}, *s_reference), 4.0, 0.3); }
TEST_F(Convergence, Dp5IsFifthOrder) { EXPECT_NEAR(fittedOrder(Method::Dp5, {1.2e-2, 8e-3, 6e-3, 4e-3}, *s_reference), 5.0, 0.3); }
TEST_F(Convergence, Hairer10IsAtLeastNinthOrder) {
    EXPECT_GE(fittedOrder(Method::Hairer10, {6e-2, 4.8e-2, 4e-2, 3e-2}, *s_reference), 9.0);
}

TEST(AdaptiveDp5, ErrorFollowsTheTolerance) {
    // The controller keeps the local error near the tolerance: tightening it by 1e3 shrinks the
    // global error by orders of magnitude and costs about 1e3^(1/5) = 4x the steps.
    Scene scene = ljPairScene(Method::Dp5, 1e-2);
    scene.integrator.adaptive = true;
    auto stepsAndError = [&](double tol) {
        scene.integrator.tolerance = tol;
        auto sim = makeSimulation(scene, ljPairState(1.25, 0.3, 0.6));
        int steps = 0;
        int rejected = 0;
        while (sim->time() < kEndTime) {
            rejected += sim->step().rejectedSteps;
            ++steps;
        }
        // Reference at the exact time the adaptive run ended.
        Scene ref = ljPairScene(Method::Hairer10, sim->time() / 600);
        auto refSim = makeSimulation(ref, ljPairState(1.25, 0.3, 0.6));
        for (int s = 0; s < 600; ++s) refSim->step();
        EXPECT_LT(rejected, steps);
        return std::make_pair(steps, errorAgainst(sim->state(), refSim->state()));
    };
    const auto loose = stepsAndError(1e-6);
    const auto tight = stepsAndError(1e-9);
    EXPECT_LT(loose.second, 1e-4);
    EXPECT_LT(tight.second, 1e-7);
    EXPECT_LT(tight.second, loose.second / 100);
    EXPECT_GT(tight.first, 2 * loose.first);
    EXPECT_LT(tight.first, 8 * loose.first);
}
