// The pair force must be -dU/dR of the pair energy, for every shift mode and mixing value, and the
// shifts must do what they promise at the cutoff.
#include <gtest/gtest.h>

#include <cmath>

#include "pair_potential.h"

using namespace corebox;

namespace {

PairCoefficients<double> makePair(double sigma, double eps, double mixing, double cutoff, CutoffShift shift) {
    PairCoefficients<double> p;
    p.sigma2 = sigma * sigma;
    p.eps4 = 4 * eps;
    p.mixing = mixing;
    p.cutoff = cutoff;
    p.cutoff2 = cutoff * cutoff;
    p.shift = int(shift);
    computeCutoffShift(p.sigma2, p.eps4, mixing, cutoff, shift, &p.energyShift, &p.forceAtCutoff);
    return p;
}

double energyAt(const PairCoefficients<double>& p, double r) {
    double u = 0;
    pairForceOverR(p, r * r, &u);
    return u;
}

}  // namespace

TEST(PairPotential, ForceIsMinusEnergyDerivativeForEveryShiftAndMixing) {
    for (CutoffShift shift : {CutoffShift::None, CutoffShift::Energy, CutoffShift::Force}) {
        for (double mixing : {0.0, 0.3, 1.0, 1.7}) {
            for (double cutoff : {0.0, 2.5}) {
                const PairCoefficients<double> p = makePair(1.1, 0.8, mixing, cutoff, shift);
                for (double r = 0.9; r < 2.45; r += 0.05) {
                    const double h = 1e-6;
                    const double numeric = -(energyAt(p, r + h) - energyAt(p, r - h)) / (2 * h);
                    const double analytic = pairForceOverR(p, r * r, static_cast<double*>(nullptr)) * r;
                    EXPECT_NEAR(analytic, numeric, 1e-6 * (1 + std::fabs(analytic)))
                        << "shift " << int(shift) << " mixing " << mixing << " cutoff " << cutoff << " r " << r;
                }
            }
        }
    }
}

TEST(PairPotential, MinimumSitsWhereTheMixingPutsIt) {
    // dU/dR = 0 at (sigma/R)^6 = x/2, i.e. R_min = sigma (2/x)^(1/6); depth eps x^2.
    for (double mixing : {0.5, 1.0}) {
        const PairCoefficients<double> p = makePair(1.0, 1.0, mixing, 0.0, CutoffShift::None);
        const double rmin = std::pow(2.0 / mixing, 1.0 / 6.0);
        EXPECT_NEAR(pairForceOverR(p, rmin * rmin, static_cast<double*>(nullptr)), 0.0, 1e-12);
        EXPECT_NEAR(energyAt(p, rmin), -mixing * mixing, 1e-12);
    }
}

TEST(PairPotential, ShiftsMakeEnergyAndForceContinuousAtTheCutoff) {
    const double rc = 2.5, below = rc * (1 - 1e-9);
    const PairCoefficients<double> none = makePair(1, 1, 1, rc, CutoffShift::None);
    const PairCoefficients<double> energy = makePair(1, 1, 1, rc, CutoffShift::Energy);
    const PairCoefficients<double> force = makePair(1, 1, 1, rc, CutoffShift::Force);
    EXPECT_GT(std::fabs(energyAt(none, below)), 1e-3);  // truncation jumps
    EXPECT_NEAR(energyAt(energy, below), 0.0, 1e-9);
    EXPECT_NEAR(energyAt(force, below), 0.0, 1e-9);
    EXPECT_NEAR(pairForceOverR(force, below * below, static_cast<double*>(nullptr)), 0.0, 1e-9);
    EXPECT_EQ(energyAt(force, rc * 1.01), 0.0);
    EXPECT_EQ(pairForceOverR(force, rc * rc * 1.02, static_cast<double*>(nullptr)), 0.0);
}

TEST(PairPotential, ZeroEpsilonSwitchesThePairOff) {
    const PairCoefficients<double> p = makePair(1, 0, 1, 0, CutoffShift::None);
    double u = 1;
    EXPECT_EQ(pairForceOverR(p, 0.5, &u), 0.0);
    EXPECT_EQ(u, 0.0);
}
