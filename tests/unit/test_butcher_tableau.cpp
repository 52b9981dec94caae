// Butcher tables: consistency (row sums) and the quadrature conditions b.c^k = 1/(k+1) up to the
// method's order, in long double so Hairer's table is checked beyond double rounding of the sums.
#include <gtest/gtest.h>

#include <cmath>

#include "butcher_tableau.h"

using namespace corebox;

namespace {

void checkTableau(const ButcherTableau& t, double tolerance) {
    for (int i = 0; i < t.stages; ++i) {
        long double rowSum = 0;
        for (int j = 0; j < i; ++j) rowSum += t.a[i][j];
        EXPECT_NEAR(double(rowSum), t.c[i], tolerance) << "row " << i;
        for (int j = i; j < t.stages; ++j) EXPECT_EQ(t.a[i][j], 0.0) << "explicit: a[" << i << "][" << j << "]";
    }
    for (int k = 0; k < t.order; ++k) {
        long double q = 0;
        for (int i = 0; i < t.stages; ++i) q += (long double)t.b[i] * std::pow((long double)t.c[i], k);
        EXPECT_NEAR(double(q), 1.0 / (k + 1), tolerance) << "quadrature condition k = " << k;
    }
    // Second-level condition sum b_i a_ij c_j = 1/6 (order >= 3).
    if (t.order >= 3) {
        long double s = 0;
        for (int i = 0; i < t.stages; ++i)
            for (int j = 0; j < i; ++j) s += (long double)t.b[i] * t.a[i][j] * t.c[j];
        EXPECT_NEAR(double(s), 1.0 / 6.0, tolerance);
    }
}

}  // namespace

TEST(ButcherTableau, ClassicalMethodsSatisfyTheirConditions) {
    checkTableau(eulerTableau(), 1e-15);
    checkTableau(rk2MidpointTableau(), 1e-15);
    checkTableau(rk4Tableau(), 1e-15);
    checkTableau(dormandPrince5Tableau(), 1e-15);
}

TEST(ButcherTableau, Hairer10HasSeventeenStagesAndOrderTenQuadrature) {
    const ButcherTableau t = hairer10Tableau();
    EXPECT_EQ(t.stages, 17);
    EXPECT_EQ(t.order, 10);
    checkTableau(t, 1e-14);
    EXPECT_DOUBLE_EQ(t.c[16], 1.0);
}

TEST(ButcherTableau, DormandPrinceEmbeddedWeightsDifferAndSkipTheLastStageWhenFixed) {
    const ButcherTableau t = dormandPrince5Tableau();
    EXPECT_EQ(t.embeddedOrder, 4);
    double errorSum = 0;
    for (int i = 0; i < t.stages; ++i) errorSum += t.bError[i];
    EXPECT_NEAR(errorSum, 0.0, 1e-15);  // both weight sets sum to one
    EXPECT_EQ(t.solutionStages, 6);
}

TEST(ButcherTableau, VerletHasNoTableau) { EXPECT_THROW(tableauFor(Method::Verlet), std::invalid_argument); }
