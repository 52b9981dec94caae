// The study (study.h) on the bound LJ pair, on the CPU:
// - from its own output (observedOrder over its ladder against its Hairer 10 reference) it recovers
//   each method's order of convergence: 1 (euler), 2 (rk2, verlet), 4 (rk4, forest_ruth, pefrl,
//   blanes_moan), 5 (dp5), 6 (yoshida6), 8 (yoshida8), within 0.5 (0.75 for 8; the ladder is shared by all
//   methods, so each fits over the few steps where its error is neither saturated nor at round-off;
//   hairer10 reaches round-off within the ladder and is only checked to be at least 8);
// - the reference is checked by its own half step and its error is far below the errors fitted;
// - its stability search finds RK4's limit on the small-amplitude oscillation within 5% of the
//   linear bound 2.83 / omega, failing by energy growth;
// - adaptive dp5 lands on the horizon and a tighter tolerance gives a smaller error for more passes.
#include <gtest/gtest.h>

#include <cmath>

#include "lj_pair.h"
#include "study.h"

using namespace corebox;
using namespace corebox::testing;

namespace {

StudyOptions pairOptions() {
    StudyOptions o;
    o.backend = "cpu";
    o.threads = 1;
    o.precisions = {Precision::Fp64};
    o.quiet = true;
    return o;
}

}  // namespace

TEST(Study, RecoversEveryMethodsOrderOnTheLjPair) {
    StudyOptions o = pairOptions();
    o.stability = false;
    o.dtFactors = {8, 4, 2, 1, 0.5, 0.25, 0.125, 0.0625};  // dt 0.048 .. 3e-4
    o.tolerances = {1e-6, 1e-9};
    o.horizon = 1.2;
    o.longRun = 2.4;
    const Scene scene = ljPairScene(Method::Rk4, 0.006);
    const StudyResult r = runStudy(scene, ljPairState(1.25, 0.3, 0.6), o);
    EXPECT_LT(r.referenceError, 1e-12);
    const struct {
        Method method;
        double order;
    } expected[] = {{Method::Euler, 1},      {Method::Rk2, 2},    {Method::Verlet, 2},     {Method::Rk4, 4},
                    {Method::ForestRuth, 4}, {Method::Pefrl, 4},  {Method::BlanesMoan, 4}, {Method::Dp5, 5},
                    {Method::Yoshida6, 6},   {Method::Yoshida8, 8}};
    for (const auto& e : expected) {
        const double order = observedOrder(r, e.method, Precision::Fp64);
        RecordProperty(std::string("order_") + methodName(e.method), std::to_string(order));
        // Yoshida 8 has two or three steps of the shared ladder between saturation and round-off,
        // where the next-order term still shows: a wider band for it.
        EXPECT_NEAR(order, e.order, e.order >= 8 ? 0.75 : 0.5) << methodName(e.method);
    }
    EXPECT_GE(observedOrder(r, Method::Hairer10, Precision::Fp64), 8.0);
    // Adaptive dp5: both tolerances land on T (a state error exists), the tighter is more accurate.
    const StudyRun* loose = nullptr;
    const StudyRun* tight = nullptr;
    for (const StudyRun& run : r.runs) {
        if (run.method == Method::Dp5 && run.tolerance == 1e-6) loose = &run;
        if (run.method == Method::Dp5 && run.tolerance == 1e-9) tight = &run;
    }
    ASSERT_TRUE(loose && tight);
    EXPECT_LT(tight->stateError, 0.1 * loose->stateError);
    EXPECT_GT(tight->forcePassesPerTime, loose->forcePassesPerTime);
}

TEST(Study, FindsRk4sStabilityLimitOnTheSmallOscillation) {
    // The pair 0.1% off the potential's minimum (unshifted, as the linear theory assumes): the
    // search starts at omega dt = 1, doubles to 2 (stable) and 4 (unstable), then bisects.
    const double omega = ljPairOmega();
    StudyOptions o = pairOptions();
    o.methods = {Method::Rk4};
    o.dtFactors = {1};
    o.tolerances = {};
    o.horizon = 2 * M_PI / omega;
    o.longRun = 200 * 2 * M_PI / omega;
    // The oscillation carries 6e-5 of the energy scale (3: the thermal energy of the scene's initial
    // temperature): a growth to 3e-4 is an instability here. With the default 1% the weakly unstable
    // steps grow until the anharmonic pair's frequency has softened below the limit and saturate
    // (omega dt 2.94 kept its energy within 0.01 of the minimum for 200 periods).
    o.driftLimit = 1e-4;
    const Scene scene = ljPairScene(Method::Rk4, 1.0 / omega, 0.0, CutoffShift::None);
    const StudyResult r = runStudy(scene, ljPairState(std::pow(2.0, 1.0 / 6.0) + 1e-3, 0, 0), o);
    ASSERT_EQ(r.limits.size(), 1u);
    const StabilityLimit& l = r.limits[0];
    RecordProperty("rk4_stable_omega_dt", std::to_string(l.stableDt * omega));
    EXPECT_NEAR(l.stableDt * omega, 2.83, 0.05 * 2.83);
    EXPECT_GT(l.unstableDt, l.stableDt);
    EXPECT_LT(l.unstableDt / l.stableDt, 1.01);
    EXPECT_EQ(l.failure, "energy_growth");
}

TEST(Study, NamesTheKindOfFailure) {
    EXPECT_EQ(instabilityKind("instability at step 3 (t = 1): 2 particle(s) with non-finite position or velocity"), "non_finite");
    EXPECT_EQ(instabilityKind("instability at step 3: 1 particle(s) escaped the box (e.g. particle 4)"), "escape");
    EXPECT_EQ(instabilityKind("instability at step 3: energy drift beyond the bound: ..."), "energy_growth");
    EXPECT_EQ(instabilityKind("adaptive dp5 could not meet tolerance 1e-8"), "adaptive_failed");
    EXPECT_EQ(instabilityKind("instability at step 9: the energy is not finite: E_kin = nan"), "non_finite");
    EXPECT_EQ(instabilityKind("instability at step 9: energy is growing without bound: kinetic energy 1e9 exceeds the runaway "
                                   "bound 20"),
              "runaway");
}
