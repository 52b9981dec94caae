// Linear stability on an oscillating LJ pair: a pair displaced by 0.1% from the minimum of the
// unshifted potential oscillates at omega = sqrt(2 U''(r_min)) (reduced mass 1/2). For each method
// omega*dt is scanned upward in steps of 0.01; a run of 200 periods counts as unstable when the
// oscillation energy E - U_min grew beyond twice its start. The first unstable omega*dt must lie
// within 25% of the linear limit on the imaginary axis: rk4 2.83, verlet 2, hairer10 1.16, dp5 1.0.
// Euler and rk2 must gain energy at every dt. A blow-up must be stopped by the simulation's checks
// (InstabilityError) before any value turns into NaN.
#include <gtest/gtest.h>

#include <cmath>

#include "errors.h"
#include "lj_pair.h"

using namespace corebox;
using namespace corebox::testing;

namespace {

constexpr double kAmplitude = 1e-3;
constexpr double kPeriods = 400;
constexpr double kGrowth = 0.02;

struct Oscillation {
    double growth;  // largest oscillation energy E - U_min in the last quarter over that in the first
    bool blewUp;    // stopped by the simulation's instability checks
};

// Sampling the peak of each quarter, not the end value, makes the test fair to verlet, whose energy
// oscillates (boundedly) at large omega*dt instead of drifting.
Oscillation oscillate(Method method, double omegaDt, double periods = kPeriods) {
    const double omega = ljPairOmega();
    const double rmin = std::pow(2.0, 1.0 / 6.0);
    Scene scene = ljPairScene(method, omegaDt / omega, 0.0, CutoffShift::None);
    auto sim = makeSimulation(scene, ljPairState(rmin + kAmplitude, 0, 0));
    const double uMin = -1.0;
    const int64_t steps = int64_t(periods * 2 * M_PI / omegaDt);
    double firstPeak = 0, lastPeak = 0;
    try {
        for (int64_t s = 0; s < steps; ++s) {
            sim->step();
            const EnergySums e = sim->backend().energies();
            const double oscillation = e.kinetic + e.potential - uMin;
            if (s < steps / 4) firstPeak = std::max(firstPeak, oscillation);
            if (s >= steps - steps / 4) lastPeak = std::max(lastPeak, oscillation);
        }
    } catch (const InstabilityError&) {
        return {INFINITY, true};
    }
    return {lastPeak / firstPeak, false};
}

double firstUnstable(Method method) {
    for (double omegaDt = 0.7; omegaDt < 4.0; omegaDt += 0.01) {
        const Oscillation o = oscillate(method, omegaDt);
        if (o.blewUp || o.growth > 1.0 + kGrowth) return omegaDt;
    }
    return INFINITY;
}

}  // namespace

TEST(Stability, LimitsMatchLinearTheoryAndRankRk4VerletHairerDp5) {
    const double rk4 = firstUnstable(Method::Rk4);
    const double verlet = firstUnstable(Method::Verlet);
    const double hairer = firstUnstable(Method::Hairer10);
    const double dp5 = firstUnstable(Method::Dp5);
    RecordProperty("rk4", std::to_string(rk4));
    RecordProperty("verlet", std::to_string(verlet));
    RecordProperty("hairer10", std::to_string(hairer));
    RecordProperty("dp5", std::to_string(dp5));
    EXPECT_NEAR(rk4, 2.83, 0.25 * 2.83);
    EXPECT_NEAR(verlet, 2.0, 0.25 * 2.0);
    EXPECT_NEAR(hairer, 1.16, 0.25 * 1.16);
    EXPECT_NEAR(dp5, 1.0, 0.25 * 1.0);
    EXPECT_GT(rk4, verlet);
    EXPECT_GT(verlet, hairer);
    EXPECT_GT(verlet, dp5);
}

TEST(Stability, EulerAndRk2GainEnergyAtEveryStepSize) {
    for (Method m : {Method::Euler, Method::Rk2}) {
        for (double omegaDt : {0.01, 0.05, 0.2, 0.5}) {
            const Oscillation o = oscillate(m, omegaDt, 20);
            EXPECT_GT(o.growth, 1.0) << methodName(m) << " at omega*dt = " << omegaDt;
        }
    }
}

TEST(Stability, StableMethodsBelowTheirLimitDoNotGainEnergy) {
    EXPECT_LE(oscillate(Method::Rk4, 2.0).growth, 1.0 + 1e-9);
    EXPECT_LE(oscillate(Method::Dp5, 0.7).growth, 1.0 + 1e-9);
    EXPECT_LE(oscillate(Method::Hairer10, 0.9).growth, 1.0 + 1e-9);
    // Verlet is symplectic: no drift, the peaks of its bounded energy oscillation stay put.
    EXPECT_NEAR(oscillate(Method::Verlet, 1.5).growth, 1.0, 1e-3);
}

TEST(Stability, ABlowUpIsStoppedAndReportedBeforeAnyNaN) {
    for (Method m : {Method::Euler, Method::Rk2, Method::Rk4, Method::Dp5, Method::Hairer10, Method::Verlet}) {
        const double omega = ljPairOmega();
        const double rmin = std::pow(2.0, 1.0 / 6.0);
        Scene scene = ljPairScene(m, 3.5 / omega, 0.0, CutoffShift::None);
        auto sim = makeSimulation(scene, ljPairState(rmin + 0.05, 0, 0));
        bool stopped = false;
        try {
            for (int s = 0; s < 100000; ++s) {
                sim->step();
                if (s % 10 == 0) {
                    const ObservablesRow row = sim->observe();
                    ASSERT_TRUE(std::isfinite(row.total())) << methodName(m) << ": NaN reached the observables";
                }
            }
        } catch (const InstabilityError& e) {
            stopped = true;
            const std::string msg = e.what();
            EXPECT_NE(msg.find("instability at step"), std::string::npos) << msg;
            EXPECT_NE(msg.find(methodName(m)), std::string::npos) << msg;
            EXPECT_NE(msg.find("dt"), std::string::npos) << msg;
        }
        EXPECT_TRUE(stopped) << methodName(m) << " at omega*dt = 3.5 was not stopped";
        const ParticleState good = sim->lastGoodState();
        for (size_t i = 0; i < good.size(); ++i) {
            for (int a = 0; a < 3; ++a) {
                EXPECT_TRUE(std::isfinite(good.position[i][a]) && std::isfinite(good.velocity[i][a])) << methodName(m);
            }
        }
    }
}
