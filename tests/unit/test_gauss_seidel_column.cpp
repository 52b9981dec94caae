// The CPU's contact sweeps (kernels/contact_relaxation.h: stopPairContact, stopWallContact, in the
// Gauss-Seidel schedule of the CPU backend: the floor first, then the contacts bottom-up), on a column
// of balls standing on the floor just after gravity's kick. Over-relaxed (kGaussSeidelOverRelaxation)
// the sweeps stop a deep column in a fraction of the plain ones, and no single update, over-relaxed
// or clamped, ever raises the kinetic energy; bouncing targets are reached exactly, not overshot.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "contact_relaxation.h"

using namespace corebox;

namespace {

constexpr double kG = 9.81;
constexpr double kDt = 1.0 / 240.0;
constexpr double kSpeedTolerance = 0.1 * kG * kDt;  // collision_rounds.cpp
constexpr int kCap = 100000;

struct GaussSeidelColumn {
    std::vector<Vec3<double>> x, v;
    std::vector<double> lambda;  // [0]: the floor; [k]: balls k - 1 and k
    double mass = 1;

    // n touching balls of diameter 1 on the floor (y up), all moving down at g dt.
    explicit GaussSeidelColumn(int n) {
        for (int i = 0; i < n; ++i) {
            x.push_back({15, 0.5 + i, 15});
            v.push_back({0, -kG * kDt, 0});
        }
        lambda.assign(size_t(n), 0);
    }

    double kinetic() const {
        double e = 0;
        for (const auto& vi : v) e += 0.5 * mass * norm2(vi);
        return e;
    }

    double fastest() const {
        double s = 0;
        for (const auto& vi : v) s = std::max(s, std::sqrt(norm2(vi)));
        return s;
    }

    // One sweep bottom-up; `afterUpdate` sees the state after every single contact update.
    template <class AfterUpdate>
    ContactResidual<double> sweep(double omega, AfterUpdate&& afterUpdate) {
        ContactResidual<double> r{0, 0};
        stopWallContact(v[0][1], 1.0, 0.0, lambda[0], r, omega);
        afterUpdate();
        for (size_t k = 1; k < v.size(); ++k) {
            // The CPU's contact (i, partner > i): the lower ball is i, the normal from the upper to it.
            const Vec3<double> rij = x[k - 1] - x[k];
            stopPairContact(v[k - 1], v[k], pairMassesOf(mass, mass), (1.0 / std::sqrt(norm2(rij))) * rij, 0.0,
                            lambda[k], r, omega);
            afterUpdate();
        }
        return r;
    }

    int sweepsToStop(double omega) {
        for (int s = 1; s <= kCap; ++s) {
            sweep(omega, [] {});
            if (fastest() <= kSpeedTolerance) return s;
        }
        return kCap;
    }
};

TEST(GaussSeidelColumn, OverRelaxedSweepsStopADeepColumnInAFractionOfThePlainSweeps) {
    GaussSeidelColumn plain(40), overRelaxed(40);
    const int plainSweeps = plain.sweepsToStop(1.0);
    const int overRelaxedSweeps = overRelaxed.sweepsToStop(kGaussSeidelOverRelaxation);
    ASSERT_LT(plainSweeps, kCap) << "plain Gauss-Seidel did not stop the column";
    ASSERT_LT(overRelaxedSweeps, kCap) << "over-relaxed Gauss-Seidel did not stop the column";
    std::printf("column of 40: stopped after %d plain Gauss-Seidel sweeps, %d over-relaxed\n", plainSweeps, overRelaxedSweeps);
    // The measured 40-layer pile needed it (contact_relaxation.h): at least five times fewer sweeps.
    EXPECT_LE(overRelaxedSweeps * 5, plainSweeps);
    for (double l : overRelaxed.lambda) EXPECT_GE(l, 0.0);
    // At rest on the floor the floor carries the whole column's momentum: n m g dt.
    EXPECT_NEAR(overRelaxed.lambda[0], 40 * kG * kDt, 40 * kSpeedTolerance);
}

TEST(GaussSeidelColumn, NoUpdateRaisesTheKineticEnergy) {
    for (int n : {2, 5, 17, 40}) {
        for (double omega : {1.0, kGaussSeidelOverRelaxation, 1.99}) {
            GaussSeidelColumn c(n);
            double last = c.kinetic();
            int updates = 0;
            for (int s = 0; s < 200; ++s)
                c.sweep(omega, [&] {
                    const double now = c.kinetic();
                    EXPECT_LE(now, last * (1 + 1e-12) + 1e-300) << n << " balls, omega " << omega << ", update " << updates;
                    last = now;
                    ++updates;
                });
        }
    }
}

TEST(GaussSeidelColumn, ABouncingTargetIsReachedExactlyNotOverRelaxed) {
    // An isolated pair approaching at 2 with restitution 0.5 leaves at 1 after one update.
    Vec3<double> vi{0, 1, 0}, vj{0, -1, 0};
    double lambda = 0;
    ContactResidual<double> r{0, 0};
    stopPairContact(vi, vj, pairMassesOf(1.0, 1.0), Vec3<double>{0, -1, 0}, 1.0, lambda, r, kGaussSeidelOverRelaxation);
    EXPECT_NEAR(vi[1], -0.5, 1e-15);
    EXPECT_NEAR(vj[1], 0.5, 1e-15);
    double w = -2, wallLambda = 0;
    stopWallContact(w, 1.0, 1.0, wallLambda, r, kGaussSeidelOverRelaxation);
    EXPECT_NEAR(w, 1.0, 1e-15);
}

}  // namespace
