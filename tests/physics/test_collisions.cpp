// Hard-core and wall collisions resolved a posteriori: the analytic two-body results, exact
// momentum, the energy loss formula, Newton's cradle, no overlap left, inelastic walls, and a ball
// that settles on the floor without hanging the step. Every test runs on each backend present (cpu,
// cuda); the tolerances are those of fp64 round-off, which the GPU meets too (it differs from the CPU
// only in rounding order).
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "physics_fixtures.h"

using namespace corebox;
using namespace corebox::testing;

namespace {

// Two spheres on the x axis approaching each other, far from the walls.
struct TwoBody {
    Scene scene;
    std::unique_ptr<Simulation> sim;
    TwoBody(const std::string& backend, double m1, double m2, double v1, double v2, double restitution) {
        scene = hardSphereScene(0, 20.0);
        SpeciesDef a = scene.species[0], b = scene.species[0];
        a.name = "a";
        a.count = 1;
        a.mass = m1;
        b.name = "b";
        b.count = 1;
        b.mass = m2;
        scene.species = {a, b};
        scene.interaction.restitution = restitution;
        scene.interaction.elasticBelowSpeed = 0;
        sim =
            makeSimulation(backend, scene, stateOf({{9.0, 10, 10}, {10.2, 10, 10}}, {{v1, 0, 0}, {v2, 0, 0}}, {0, 1}));
    }
    void run(int steps) {
        for (int s = 0; s < steps; ++s) sim->step();
    }
    Vec3<double> velocity(int i) const { return sim->state().velocity[size_t(i)]; }
};

class Collisions : public OnEveryBackend {};

}  // namespace

INSTANTIATE_TEST_SUITE_P(Backends, Collisions, ::testing::ValuesIn(backendNames()), backendInstanceName);

TEST_P(Collisions, HeadOnEqualMassesExchangeVelocities) {
    TwoBody t(backendName(), 1, 1, 1.0, -0.5, 1.0);
    t.run(400);
    EXPECT_NEAR(t.velocity(0).x, -0.5, 1e-12);
    EXPECT_NEAR(t.velocity(1).x, 1.0, 1e-12);
    EXPECT_EQ(t.sim->observe().collisionsPair, 1);
}

TEST_P(Collisions, UnequalMassesMatchTheAnalyticResult) {
    const double m1 = 1, m2 = 4, u1 = 1.0, u2 = -0.25, e = 0.7;
    TwoBody t(backendName(), m1, m2, u1, u2, e);
    t.run(400);
    // v1 = (m1 u1 + m2 u2 - m2 e (u1 - u2)) / (m1 + m2), v2 = (m1 u1 + m2 u2 + m1 e (u1 - u2)) / (m1 + m2)
    const double p = m1 * u1 + m2 * u2;
    EXPECT_NEAR(t.velocity(0).x, (p - m2 * e * (u1 - u2)) / (m1 + m2), 1e-12);
    EXPECT_NEAR(t.velocity(1).x, (p + m1 * e * (u1 - u2)) / (m1 + m2), 1e-12);
}

TEST_P(Collisions, EnergyLossEqualsTheFormulaAndIsCountedAsDissipated) {
    const double m1 = 2, m2 = 3, u1 = 0.8, u2 = -0.6, e = 0.5;
    TwoBody t(backendName(), m1, m2, u1, u2, e);
    const double before = t.sim->observe().kinetic;
    t.run(400);
    const ObservablesRow row = t.sim->observe();
    const double mu = m1 * m2 / (m1 + m2), vn = u2 - u1;  // the normal points from b to a: n = -x
    const double expected = 0.5 * (1 - e * e) * mu * vn * vn;
    EXPECT_NEAR(before - row.kinetic, expected, 1e-12);
    EXPECT_NEAR(row.dissipated, expected, 1e-12);
    EXPECT_NEAR(row.conserved(), before, 1e-12);
}

TEST_P(Collisions, OffCentreImpulseActsAlongTheLineOfCentres) {
    Scene scene = hardSphereScene(2, 20.0);
    auto sim =
        makeSimulation(backendName(), scene, stateOf({{9.0, 10.0, 10}, {10.5, 10.5, 10}}, {{1, 0, 0}, {0, 0, 0}}));
    for (int s = 0; s < 1000; ++s) sim->step();
    const ParticleState st = sim->state();
    // Equal masses, elastic: the velocities end up perpendicular and the speeds add in quadrature.
    EXPECT_NEAR(dot(st.velocity[0], st.velocity[1]), 0.0, 1e-12);
    EXPECT_NEAR(norm2(st.velocity[0]) + norm2(st.velocity[1]), 1.0, 1e-12);
    EXPECT_NEAR(st.velocity[0].x + st.velocity[1].x, 1.0, 1e-12);
    EXPECT_NEAR(st.velocity[0].y + st.velocity[1].y, 0.0, 1e-12);
}

TEST_P(Collisions, MomentumIsConservedToRoundOffWithoutWalls) {
    // A dense cluster in the middle of a huge box: many collisions, none with a wall.
    Scene scene = hardSphereScene(0, 200.0);
    scene.species[0].count = 125;
    scene.interaction.restitution = 0.8;
    ParticleState st;
    for (int i = 0; i < 5; ++i)
        for (int j = 0; j < 5; ++j)
            for (int k = 0; k < 5; ++k) {
                st.position.push_back({100 + 1.05 * i, 100 + 1.05 * j, 100 + 1.05 * k});
                const double phase = 0.7 * i + 1.3 * j + 2.1 * k;
                st.velocity.push_back({std::sin(phase), std::cos(2 * phase), std::sin(3 * phase + 1)});
                st.species.push_back(0);
            }
    auto sim = makeSimulation(backendName(), scene, st);
    const ObservablesRow first = sim->observe();
    double scale = 0;
    for (const auto& v : st.velocity) scale += std::sqrt(norm2(v));
    int64_t collisions = 0;
    for (int s = 0; s < 2000; ++s) collisions += sim->step().pairCollisions;
    const ObservablesRow last = sim->observe();
    EXPECT_GT(collisions, 100);
    EXPECT_EQ(last.collisionsWall, 0);
    EXPECT_LT(std::fabs(last.px - first.px) / scale, 1e-12);
    EXPECT_LT(std::fabs(last.py - first.py) / scale, 1e-12);
    EXPECT_LT(std::fabs(last.pz - first.pz) / scale, 1e-12);
}

TEST_P(Collisions, NewtonsCradlePassesTheMomentumToTheLastBall) {
    Scene scene = hardSphereScene(5, 30.0);
    ParticleState st;
    st.position.push_back({5.0, 15, 15});
    st.velocity.push_back({1.0, 0, 0});
    for (int i = 0; i < 4; ++i) {
        st.position.push_back({8.0 + 1.0 * i, 15, 15});  // touching row
        st.velocity.push_back({0, 0, 0});
    }
    st.species.assign(5, 0);
    auto sim = makeSimulation(backendName(), scene, st);
    for (int s = 0; s < 3000; ++s) sim->step();
    const ParticleState end = sim->state();
    for (int i = 0; i < 4; ++i) EXPECT_NEAR(end.velocity[size_t(i)].x, 0.0, 1e-9) << "ball " << i;
    EXPECT_NEAR(end.velocity[4].x, 1.0, 1e-9);
}

TEST_P(Collisions, NoOverlapIsLeftAfterAStep) {
    Scene scene = hardSphereScene(0, 8.0, Method::Rk4, 5e-3);
    scene.species[0].count = 300;  // packing fraction 0.31
    scene.init.temperature = 2.0;
    scene.interaction.restitution = 0.9;
    scene.box.wallRestitution = 0.9;
    auto sim = makeSimulation(backendName(), scene);
    double worst = 0;
    int64_t collisions = 0;
    for (int s = 0; s < 300; ++s) {
        const StepReport r = sim->step();
        collisions += r.pairCollisions;
        EXPECT_FALSE(r.roundCapHit);
        const ParticleState st = sim->state();
        for (size_t i = 0; i < st.size(); ++i) {
            for (size_t j = i + 1; j < st.size(); ++j)
                worst = std::max(worst, 1.0 - std::sqrt(norm2(st.position[i] - st.position[j])));
            for (int a = 0; a < 3; ++a) {
                worst = std::max(worst, 0.5 - st.position[i][a]);
                worst = std::max(worst, st.position[i][a] - 7.5);
            }
        }
    }
    EXPECT_GT(collisions, 500);
    EXPECT_LT(worst, 1e-9);
}

TEST_P(Collisions, WallReflectsWithItsRestitution) {
    Scene scene = hardSphereScene(1, 10.0);
    scene.box.wallRestitution = 0.6;
    scene.interaction.elasticBelowSpeed = 0;
    auto sim = makeSimulation(backendName(), scene, stateOf({{8.0, 5, 5}}, {{2.0, 0.3, 0}}));
    for (int s = 0; s < 1000; ++s) sim->step();  // hits x = 9.5 at t = 0.75, then travels back
    const ParticleState st = sim->state();
    EXPECT_NEAR(st.velocity[0].x, -1.2, 1e-12);
    EXPECT_NEAR(st.velocity[0].y, 0.3, 1e-12);
    EXPECT_NEAR(st.position[0].x, 9.5 - 1.2 * 0.25, 1e-9);
    const ObservablesRow row = sim->observe();
    EXPECT_EQ(row.collisionsWall, 1);
    EXPECT_NEAR(row.dissipated, 0.5 * (1 - 0.36) * 4.0, 1e-12);
}

TEST_P(Collisions, BouncingBallSettlesWithoutHanging) {
    Scene scene = hardSphereScene(1, 10.0, Method::Verlet, 1e-3);
    scene.interaction.gravity = {0, 0, -9.81};
    scene.box.wallRestitution = 0.7;
    auto sim = makeSimulation(backendName(), scene, stateOf({{5, 5, 4.0}}, {{0, 0, 0}}));
    const double e0 = sim->observe().conserved();
    double lastPeak = 0;
    for (int s = 0; s < 20000; ++s) {  // 20 time units: dozens of bounces, then rest
        const StepReport r = sim->step();
        EXPECT_FALSE(r.roundCapHit);
        if (s > 15000) lastPeak = std::max(lastPeak, sim->state().position[0].z);
        if (s == 3000) {
            const double c = sim->observe().conserved();
            RecordProperty("bouncing_relative_error", std::to_string((c - e0) / e0));
            // The parabolic rewind is exact under uniform gravity: only round-off remains.
            EXPECT_NEAR(c, e0, 1e-9 * e0);
        }
    }
    EXPECT_LT(lastPeak - 0.5, 1e-3);  // resting on the floor (centre at the radius)
    EXPECT_GE(sim->state().position[0].z, 0.5 - 1e-12);
    const ObservablesRow row = sim->observe();
    EXPECT_GT(row.dissipated, 0.99 * 9.81 * 3.5);  // nearly all the potential energy was lost
    RecordProperty("resting_relative_error", std::to_string((row.conserved() - e0) / e0));
    EXPECT_NEAR(row.conserved(), e0, 1e-9 * e0);
}
