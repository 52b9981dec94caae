// Convergence order of every integrator in fp64 on a bound, rotating and vibrating LJ pair with a
// shifted-force cutoff (smooth, no collisions). The error at t = 1.2 against a Hairer-10 reference
// at a tiny step is fitted against dt on a log-log scale; step sizes keep the error well above
// round-off (> 1e-11) and in the asymptotic range. Every test runs on each backend present (cpu,
// cuda), the reference on the same backend; the fitted orders do not depend on round-off.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "lj_pair.h"

using namespace corebox;
using namespace corebox::testing;

namespace {

constexpr double kEndTime = 1.2;

ParticleState runPair(const std::string& backend, Method method, double dt) {
    Scene scene = ljPairScene(method, dt);
    auto sim = makeSimulation(backend, scene, ljPairState(1.25, 0.3, 0.6));
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
double fittedOrder(const std::string& backend, Method method, const std::vector<double>& steps,
                   const ParticleState& reference) {
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    for (double dt : steps) {
        const double e = errorAgainst(runPair(backend, method, dt), reference);
        EXPECT_GT(e, 1e-11) << methodName(method) << " dt " << dt << ": error at round-off, slope meaningless";
        ::testing::Test::RecordProperty(std::string(methodName(method)) + "_dt_" + std::to_string(dt),
                                        std::to_string(e));
        const double x = std::log(dt), y = std::log(e);
        sx += x;
        sy += y;
        sxx += x * x;
        sxy += x * y;
    }
    const double n = double(steps.size());
    return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

class Convergence : public OnEveryBackend {
protected:
    void SetUp() override {
        OnEveryBackend::SetUp();
        if (IsSkipped()) return;
        m_reference = runPair(backendName(), Method::Hairer10, kEndTime / 600);
    }
    double order(Method method, const std::vector<double>& steps) {
        return fittedOrder(backendName(), method, steps, m_reference);
    }
    ParticleState m_reference;
};

class AdaptiveDp5 : public OnEveryBackend {};

}  // namespace

INSTANTIATE_TEST_SUITE_P(Backends, Convergence, ::testing::ValuesIn(backendNames()), backendInstanceName);
INSTANTIATE_TEST_SUITE_P(Backends, AdaptiveDp5, ::testing::ValuesIn(backendNames()), backendInstanceName);

TEST_P(Convergence, EulerIsFirstOrder) { EXPECT_NEAR(order(Method::Euler, {1.2e-3, 6e-4, 3e-4}), 1.0, 0.3); }
TEST_P(Convergence, Rk2IsSecondOrder) { EXPECT_NEAR(order(Method::Rk2, {6e-3, 3e-3, 1.5e-3}), 2.0, 0.3); }
TEST_P(Convergence, VerletIsSecondOrder) { EXPECT_NEAR(order(Method::Verlet, {6e-3, 3e-3, 1.5e-3}), 2.0, 0.3); }
TEST_P(Convergence, Rk4IsFourthOrder) { EXPECT_NEAR(order(Method::Rk4, {1.2e-2, 6e-3, 3e-3}), 4.0, 0.3); }
TEST_P(Convergence, Dp5IsFifthOrder) { EXPECT_NEAR(order(Method::Dp5, {1.2e-2, 8e-3, 6e-3, 4e-3}), 5.0, 0.3); }
TEST_P(Convergence, Hairer10IsAtLeastNinthOrder) {
    EXPECT_GE(order(Method::Hairer10, {6e-2, 4.8e-2, 4e-2, 3e-2}), 9.0);
}

// The symplectic compositions of Verlet (symplectic_composition.h): orders 4, 4, 4, 6, 8.
TEST_P(Convergence, ForestRuthIsFourthOrder) { EXPECT_NEAR(order(Method::ForestRuth, {1.2e-2, 6e-3, 3e-3}), 4.0, 0.3); }
TEST_P(Convergence, PefrlIsFourthOrder) { EXPECT_NEAR(order(Method::Pefrl, {2.4e-2, 1.2e-2, 6e-3}), 4.0, 0.3); }
TEST_P(Convergence, BlanesMoanIsFourthOrder) { EXPECT_NEAR(order(Method::BlanesMoan, {2.4e-2, 1.2e-2, 6e-3}), 4.0, 0.3); }
TEST_P(Convergence, Yoshida6IsSixthOrder) { EXPECT_NEAR(order(Method::Yoshida6, {2.4e-2, 1.6e-2, 1.2e-2}), 6.0, 0.3); }
TEST_P(Convergence, Yoshida8IsEighthOrder) { EXPECT_NEAR(order(Method::Yoshida8, {6e-2, 4e-2, 3e-2}), 8.0, 0.3); }

TEST_P(AdaptiveDp5, ErrorFollowsTheTolerance) {
    // The controller keeps the local error near the tolerance: tightening it by 1e3 shrinks the
    // global error by orders of magnitude and costs about 1e3^(1/5) = 4x the steps.
    Scene scene = ljPairScene(Method::Dp5, 1e-2);
    scene.integrator.adaptive = true;
    auto stepsAndError = [&](double tol) {
        scene.integrator.tolerance = tol;
        auto sim = makeSimulation(backendName(), scene, ljPairState(1.25, 0.3, 0.6));
        int steps = 0;
        int rejected = 0;
        while (sim->time() < kEndTime) {
            rejected += sim->step().rejectedSteps;
            ++steps;
        }
        // Reference at the exact time the adaptive run ended.
        Scene ref = ljPairScene(Method::Hairer10, sim->time() / 600);
        auto refSim = makeSimulation(backendName(), ref, ljPairState(1.25, 0.3, 0.6));
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
