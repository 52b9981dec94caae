// The GPU's Jacobi contact sweeps (kernels/contact_relaxation.h: relaxParticle, acceleratedImpulse,
// sweepMomentum; its fallback from the coloured Gauss-Seidel sweeps) run here on the host in the
// kernels' schedule: every particle from the previous
// sweep's values, then the update, in batches of eight, and the settling of the rows where the host
// stops (settleRow). On a column of balls standing on the floor just after gravity's kick (the deep
// pile in one dimension: support climbs a ball per sweep), the accelerated sweeps stop the column in a
// fraction of the plain sweeps (of the order of n instead of n^2), end with projected impulses
// (lambda >= 0, the applied impulse equal to it), and take kinetic energy out, never in; a column
// lowered into its floor is lifted out of it, and no further.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <vector>

#include "contact_relaxation.h"

using namespace corebox;

namespace {

constexpr double kG = 9.81;
constexpr double kDt = 1.0 / 240.0;
constexpr int kBatch = 8;  // collision_rounds.cpp: sweeps between residual reads

struct Column {
    int n;
    std::vector<Vec3<double>> x, v, dv, dx;
    std::vector<int32_t> species;
    std::vector<int64_t> start, partner;  // particle i's contacts: partner[start[i] .. start[i + 1])
    std::vector<double> lambda, applied;
    double mass = 1, radius = 0.5;
    int sweepsDone = 0;  // the momentum's index, as the backend counts it from the listing
    Vec3<double> box{30, 60, 30};

    // n balls on the floor, touching, all moving down at g dt; `sunk`: the column lowered that far.
    Column(int count, double sunk) : n(count) {
        for (int i = 0; i < n; ++i) {
            x.push_back({15, radius + 2 * radius * i - sunk, 15});
            v.push_back({0, -kG * kDt, 0});
            species.push_back(0);
        }
        dv.assign(size_t(n), {0, 0, 0});
        dx.assign(size_t(n), {0, 0, 0});
        start.push_back(0);
        for (int i = 0; i < n; ++i) {
            if (i == 0) partner.push_back(-1 - 2);  // the floor: axis 1, low side
            if (i > 0) partner.push_back(i - 1);
            if (i + 1 < n) partner.push_back(i + 1);
            start.push_back(int64_t(partner.size()));
        }
        lambda.assign(partner.size(), 0);
        applied.assign(partner.size(), 0);
    }

    double kinetic() const {
        double e = 0;
        for (const auto& vi : v) e += 0.5 * mass * norm2(vi);
        return e;
    }

    // One sweep and its update, as sweepKernel and applySweepKernel do it.
    ContactResidual<double> sweep(double beta) {
        ContactResidual<double> worst{0, 0};
        const ContactBounce<double> bounce{0.5, 0.5, 0, 1e9};  // nothing bounces
        for (int64_t i = 0; i < n; ++i) {
            const int64_t first = start[size_t(i)];
            ContactResidual<double> r{0, 0};
            ImpulseSums given;
            relaxParticle(
                i, int(start[size_t(i) + 1] - first), [&](int c) { return partner[size_t(first + c)]; },
                [&](int64_t j) { return int(start[size_t(j) + 1] - start[size_t(j)]); }, lambda.data() + first, x.data(), v.data(),
                species.data(), &mass, &radius, box, Vec3<double>{0, 1, 0}, bounce, dv[size_t(i)], dx[size_t(i)], r, given,
                applied.data() + first, beta);
            worst.speedChange = std::max(worst.speedChange, r.speedChange);
            worst.overlap = std::max(worst.overlap, r.overlap);
        }
        for (size_t i = 0; i < size_t(n); ++i) {
            v[i] += dv[i];
            x[i] += dx[i];
        }
        return worst;
    }

    double fastest() const {
        double s = 0;
        for (const auto& vi : v) s = std::max(s, std::sqrt(norm2(vi)));
        return s;
    }

    // endRelaxation: every row from its applied impulse to its projected one, as rowImpulsesKernel.
    void settle() {
        for (int64_t i = 0; i < n; ++i) {
            const int64_t first = start[size_t(i)];
            ImpulseSums given;
            double* l = lambda.data() + first;
            double* a = applied.data() + first;
            v[size_t(i)] += rowImpulsesOf(
                i, int(start[size_t(i) + 1] - first), [&](int c) { return partner[size_t(first + c)]; },
                [&](int c) { return settleRow(l[c], a[c]); }, x.data(), species.data(), &mass, &radius, box, given);
        }
    }

    // Batches of sweeps, as collision_rounds.cpp runs them, until `done(state the host would stop
    // with, residual of the batch's last sweep)` or `cap` sweeps; ends settled. Returns the sweeps
    // taken since the listing.
    template <class Done>
    int relax(bool accelerated, Done&& done, int cap) {
        while (sweepsDone < cap) {
            ContactResidual<double> r{0, 0};
            for (int b = 0; b < kBatch; ++b, ++sweepsDone) r = sweep(accelerated ? sweepMomentum<double>(sweepsDone) : 0.0);
            Column stopped = *this;
            stopped.settle();
            if (done(stopped, r)) break;
        }
        settle();
        return sweepsDone;
    }
};

constexpr double kSpeedTolerance = 0.1 * kG * kDt;  // collision_rounds.cpp
constexpr int kCap = 20000;

TEST(ContactSweeps, MomentumStartsAtZeroAndGrowsBelowOne) {
    EXPECT_EQ(sweepMomentum<double>(0), 0.0);
    EXPECT_EQ(sweepMomentum<double>(1), 0.0);
    double last = 0;
    for (int k = 2; k < 1000; ++k) {
        const double beta = sweepMomentum<double>(k);
        EXPECT_GT(beta, last);
        EXPECT_LT(beta, 1.0);
        last = beta;
    }
}

TEST(ContactSweeps, AcceleratedSweepsStopADeepColumnInAFractionOfThePlainSweeps) {
    // Stopped: no ball of the column moves faster than the tolerance (its local residual, the largest
    // relative speed, is small long before: the error of a chain is smooth).
    Column plain(40, 0), accelerated(40, 0);
    const double kinetic0 = plain.kinetic();
    auto stopped = [](const Column& c, const ContactResidual<double>&) { return c.fastest() <= kSpeedTolerance; };
    const int plainSweeps = plain.relax(false, stopped, kCap);
    const int acceleratedSweeps = accelerated.relax(true, stopped, kCap);
    ASSERT_LT(plainSweeps, kCap) << "plain Jacobi did not stop the column";
    ASSERT_LT(acceleratedSweeps, kCap) << "accelerated Jacobi did not stop the column";
    // Plain Jacobi needs of the order of n^2 sweeps on a chain, accelerated of the order of n.
    EXPECT_LE(acceleratedSweeps * 10, plainSweeps) << "plain " << plainSweeps << ", accelerated " << acceleratedSweeps;
    std::printf("column of 40: stopped after %d plain sweeps, %d accelerated\n", plainSweeps, acceleratedSweeps);
    for (const Column* c : {&plain, &accelerated}) {
        EXPECT_LT(c->kinetic(), kinetic0 * 1e-2);
        for (size_t k = 0; k < c->lambda.size(); ++k) {
            EXPECT_GE(c->lambda[k], 0.0);
            EXPECT_EQ(c->applied[k], c->lambda[k]) << "the measured sweep leaves the projected impulse applied";
        }
    }
}

TEST(ContactSweeps, AcceleratedSweepsNeverEndAboveTheStartingKineticEnergy) {
    // Every stopping point the host may choose (the end of each batch), for several column depths.
    for (int n : {2, 5, 17, 40}) {
        Column c(n, 0);
        const double kinetic0 = c.kinetic();
        int batches = 0;
        c.relax(true,
                [&](const Column& stopped, const ContactResidual<double>&) {
                    EXPECT_LE(stopped.kinetic(), kinetic0 * (1 + 1e-12)) << n << " balls, batch " << batches;
                    return ++batches == 64;
                },
                kCap);
    }
}

TEST(ContactSweeps, AColumnSunkIntoTheFloorIsLiftedOutOfIt) {
    const double sunk = 2e-3;  // of a diameter 1
    Column c(20, sunk);
    for (auto& vi : c.v) vi = {0, 0, 0};
    const int sweeps = c.relax(true, [](const Column&, const ContactResidual<double>& r) { return r.overlap <= 1e-5; }, kCap);
    ASSERT_LT(sweeps, kCap);
    // The floor's overlap is gone up to the tolerance, every ball went up, none by more than it sank
    // plus the tolerances of the contacts below it.
    for (int i = 0; i < c.n; ++i) {
        const double lift = c.x[size_t(i)][1] - (c.radius + 2 * c.radius * i - sunk);
        EXPECT_GT(lift, 0.5 * sunk) << "ball " << i;
        EXPECT_LT(lift, sunk + 1e-5 * (i + 1) + 1e-12) << "ball " << i;
    }
    for (const auto& vi : c.v) EXPECT_EQ(norm2(vi), 0.0) << "the position level changes no velocity";
}

TEST(ContactSweeps, ThePlanLooksAfterTheFirstSweepAndAtTheEndOfEachBatch) {
    const RelaxationPlan plan{20, 8, 0.1, 1e-3};
    std::vector<int> checks;
    for (int done = 1; done <= 20; ++done)
        if (plan.checkedAfter(done, 0.5)) checks.push_back(done);
    EXPECT_EQ(checks, (std::vector<int>{1, 9, 17, 20}));  // the last batch cut short by the cap
    EXPECT_TRUE(plan.continuesAfter(9, ContactResidual<double>{0.2, 0}, 0.5));
    EXPECT_TRUE(plan.continuesAfter(9, ContactResidual<double>{0, 2e-3}, 0.5));
    EXPECT_FALSE(plan.continuesAfter(9, ContactResidual<double>{0.1, 1e-3}, 0.5));  // within both: done
    EXPECT_FALSE(plan.continuesAfter(20, ContactResidual<double>{1, 1}, 0.5));      // the cap
}

TEST(ContactSweeps, AListingThatIsListedAgainStopsAtItsOwnCap) {
    RelaxationPlan plan{20, 8, 0.1, 1e-3};
    plan.relistOverlap = 0.02;
    plan.relistSweeps = 5;
    std::vector<int> deep, shallow;
    for (int done = 1; done <= plan.sweepCap(0.03); ++done)
        if (plan.checkedAfter(done, 0.03)) deep.push_back(done);
    for (int done = 1; done <= plan.sweepCap(0.01); ++done)
        if (plan.checkedAfter(done, 0.01)) shallow.push_back(done);
    EXPECT_EQ(deep, (std::vector<int>{1, 5}));             // deep at the first sweep: checked at its cap
    EXPECT_EQ(shallow, (std::vector<int>{1, 9, 17, 20}));  // as without the relisting cap
    const ContactResidual<double> far{1, 1};
    EXPECT_EQ(plan.sweepCap(0.02), 5);
    EXPECT_EQ(plan.sweepCap(0.0199), 20);
    EXPECT_TRUE(plan.continuesAfter(4, far, 0.03));
    EXPECT_FALSE(plan.continuesAfter(5, far, 0.03));  // deep at the first sweep: listed again after 5
    EXPECT_TRUE(plan.continuesAfter(5, far, 0.01));   // shallow: the whole cap
    plan.relistSweeps = 40;                           // above the cap: the cap
    EXPECT_EQ(plan.sweepCap(0.5), 20);
}

}  // namespace
