// Neighbour-list forces (DESIGN.md sec. 2, force_model.h): they equal the all-pairs ones, conserve
// energy through list rebuilds, keep Verlet's cached accelerations through collision steps without a
// second force pass, and give the same state on 1 and 2 threads.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "cell_list.h"
#include "device_model.h"
#include "observables.h"
#include "physics_fixtures.h"
#include "state_hash.h"

using namespace corebox;
using namespace corebox::testing;

namespace {

struct ForceCase {
    std::array<double, 3> box;
    double cutoff;
    CutoffShift shift;
};

// Two species of different sigma, mass and radius; particles at random (no pair closer than 0.75),
// plus particles a hair from the walls and from the faces of the list's cells.
Scene twoSpecies(const ForceCase& c, int64_t n) {
    Scene scene;
    SpeciesDef a, b;
    a.name = "A";
    a.count = n / 2;
    a.radius = 0.3;
    b.name = "B";
    b.count = n - n / 2;
    b.sigma = 1.4;
    b.epsilon = 0.7;
    b.mass = 2.5;
    b.radius = 0.35;
    scene.species = {a, b};
    scene.interaction.mixing = {{1.0, 0.6}, {0.6, 0.9}};
    scene.interaction.cutoff = c.cutoff;
    scene.interaction.shift = c.shift;
    scene.box.size = c.box;
    scene.thermostat.kind = ThermostatKind::None;
    return scene;
}

ParticleState awkwardState(const Scene& scene, uint64_t seed) {
    const int64_t n = scene.particleCount();
    const Vec3<double> box{scene.box.size[0], scene.box.size[1], scene.box.size[2]};
    const CellGeometry grid = cellGeometry(box, n, scene.interaction.cutoff + scene.interaction.skin);
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    std::vector<Vec3<double>> x;
    auto farEnough = [&](const Vec3<double>& p) {
        return std::all_of(x.begin(), x.end(), [&](const Vec3<double>& q) { return norm2(p - q) > 0.75 * 0.75; });
    };
    while (int64_t(x.size()) < n) {
        Vec3<double> p{unit(rng) * box.x, unit(rng) * box.y, unit(rng) * box.z};
        const int kind = int(x.size() % 4);
        const int axis = int(unit(rng) * 3) % 3;
        if (kind == 1) p[axis] = unit(rng) < 0.5 ? 1e-9 : box[axis] * (1 - 1e-15);  // at a wall
        if (kind == 2) {                                                               // on a cell face
            const double width = box[axis] / grid.dims[axis];
            const int face = int(unit(rng) * grid.dims[axis]);
            p[axis] = face * width + (unit(rng) < 0.5 ? -1e-12 : 1e-12);
            p[axis] = std::min(std::max(p[axis], 0.0), box[axis]);
        }
        if (farEnough(p)) x.push_back(p);
    }
    std::vector<int32_t> species(static_cast<size_t>(n));
    for (int64_t i = 0; i < n; ++i) species[size_t(i)] = i % 2 == 0 ? 0 : 1;
    return stateOf(x, std::vector<Vec3<double>>(size_t(n), Vec3<double>{0, 0, 0}), species);
}

struct Evaluated {
    std::vector<Vec3<double>> acceleration;
    double potential = 0;
    double virial = 0;
};

// Accelerations (as the velocities after a unit kick from rest), the potential and the pair virial.
Evaluated evaluate(const std::string& backend, const Scene& scene, const ParticleState& state, ForceModel forces) {
    std::unique_ptr<Backend> b = makeTestBackend(backend, Precision::Fp64);
    DeviceModel model = deviceModelOf(stepParametersOf(scene));
    model.forces = forces;
    b->setModel(model);
    b->setState(state);
    b->computeAccelerations();
    b->kick(1.0);
    Evaluated e;
    e.acceleration = b->state().velocity;
    b->setState(state);
    e.potential = b->energies().potential;
    e.virial = b->pairVirial();
    return e;
}

class NeighbourList : public OnEveryBackend {};

}  // namespace

INSTANTIATE_TEST_SUITE_P(Backends, NeighbourList, ::testing::ValuesIn(backendNames()), backendInstanceName);

// Relative 1e-12 in fp64: per component against the largest acceleration (a single particle's net
// force may cancel to near zero, where a relative comparison would measure the summation order).
TEST_P(NeighbourList, ForcesAndEnergiesEqualAllPairs) {
    const ForceCase cases[] = {
        {{9, 9, 9}, 2.5, CutoffShift::Force},     {{14, 7.5, 6.2}, 1.6, CutoffShift::None},
        {{20, 11, 3.1}, 3.3, CutoffShift::Energy}, {{8, 8, 8}, 4.5, CutoffShift::Force},  // cutoff beyond half the box
        {{24, 17, 15}, 2.5, CutoffShift::None},
    };
    uint64_t seed = 1;
    for (const ForceCase& c : cases) {
        // The last box is large enough for the CPU's list to cut its particles into several chunks.
        const int64_t n = c.box[0] > 20 ? 2400 : 400;
        const Scene scene = twoSpecies(c, n);
        SCOPED_TRACE("box " + std::to_string(c.box[0]) + " x " + std::to_string(c.box[1]) + " x " + std::to_string(c.box[2]) +
                     ", cutoff " + std::to_string(c.cutoff));
        const ParticleState state = awkwardState(scene, seed++);
        const Evaluated all = evaluate(backendName(), scene, state, ForceModel::AllPairs);
        const Evaluated list = evaluate(backendName(), scene, state, ForceModel::NeighbourList);
        double scale = 0;
        for (const Vec3<double>& a : all.acceleration) scale = std::max(scale, std::sqrt(norm2(a)));
        ASSERT_GT(scale, 0);
        double worst = 0;
        for (size_t i = 0; i < state.size(); ++i) worst = std::max(worst, std::sqrt(norm2(list.acceleration[i] - all.acceleration[i])) / scale);
        EXPECT_LT(worst, 1e-12);
        EXPECT_NEAR(list.potential, all.potential, 1e-12 * std::fabs(all.potential));
        EXPECT_NEAR(list.virial, all.virial, 1e-12 * std::fabs(all.virial));
        EXPECT_NE(all.potential, 0.0);
    }
}

// NVE, Verlet, fp64, shifted force, lists rebuilt as particles move: 10^4 steps of an LJ droplet
// (a 7^3 lattice at the pair-potential minimum, melting) far from the walls, whose reflections would
// add their own error.
TEST_P(NeighbourList, VerletConservesEnergyThroughRebuilds) {
    Scene scene;
    SpeciesDef s;
    s.count = 343;
    s.radius = 0.3;  // hard cores out of reach at this temperature: the force field alone
    scene.species = {s};
    scene.box.size = {16, 16, 16};
    scene.interaction.cutoff = 2.5;
    scene.interaction.shift = CutoffShift::Force;
    scene.interaction.forces = ForceModel::NeighbourList;
    scene.integrator.method = Method::Verlet;
    scene.integrator.dt = 0.002;
    scene.thermostat.kind = ThermostatKind::None;
    scene.init.temperature = 0.5;
    scene.init.seed = 5;
    std::vector<Vec3<double>> x;
    for (int i = 0; i < 7; ++i)
        for (int j = 0; j < 7; ++j)
            for (int k = 0; k < 7; ++k) x.push_back(Vec3<double>{8 + 1.12 * (i - 3), 8 + 1.12 * (j - 3), 8 + 1.12 * (k - 3)});
    ParticleState start = stateOf(x, std::vector<Vec3<double>>(x.size(), Vec3<double>{0, 0, 0}));
    assignMaxwellBoltzmannVelocities(scene, start);
    auto sim = makeSimulation(backendName(), scene, start);
    ASSERT_EQ(sim->forceChoice().model, ForceModel::NeighbourList) << sim->forceChoice().reason;
    const ObservablesRow first = sim->observe();
    const double e0 = first.conserved();
    ASSERT_LT(e0, -1.0 * 343);  // a bound liquid: |E0| is not near zero
    double worst = 0;
    for (int step = 1; step <= 10000; ++step) {
        sim->step();
        if (step % 500 == 0) worst = std::max(worst, std::fabs(sim->observe().conserved() - e0) / std::fabs(e0));
    }
    const ForceCounters counters = sim->backend().forceCounters();
    RecordProperty("list_builds", std::to_string(counters.listBuilds));
    RecordProperty("relative_energy_error", std::to_string(worst));
    std::printf("NVE over 10^4 steps: |E - E0| / |E0| <= %.3g, %lld list builds\n", worst, (long long)counters.listBuilds);
    EXPECT_LT(worst, 1e-4);
    if (backendName() == "cpu") {
        EXPECT_GT(counters.listBuilds, 10);     // the skin is used up many times over 20 tau...
        EXPECT_LT(counters.listBuilds, 2000);   // ...but far from every step
    }
}

namespace {

// A hot gas whose hard cores (diameter 1) collide every step, with a weak LJ tail (sigma 0.6) and a cutoff.
Scene collidingGas(ForceModel forces) {
    Scene scene;
    SpeciesDef s;
    s.count = 600;
    s.sigma = 0.6;
    s.radius = 0.5;
    scene.species = {s};
    scene.box.size = {13, 12, 11};
    scene.interaction.cutoff = 2.0;
    scene.interaction.forces = forces;
    scene.interaction.skin = 0.5;
    scene.integrator.method = Method::Verlet;
    scene.integrator.dt = 0.004;
    scene.thermostat.kind = ThermostatKind::None;
    scene.init.temperature = 2.0;
    scene.init.placement = Placement::Random;
    scene.init.seed = 11;
    return scene;
}

}  // namespace

// One full force pass per Verlet step (plus the first step's), however many collisions: the moved
// particles' accelerations are refreshed, and they equal a fresh full pass.
TEST(NeighbourListCpu, CollisionStepsCostNoSecondForcePass) {
    for (ForceModel forces : {ForceModel::AllPairs, ForceModel::NeighbourList}) {
        SCOPED_TRACE(forceModelName(forces));
        const Scene scene = collidingGas(forces);
        auto sim = makeSimulation("cpu", scene);
        ASSERT_EQ(sim->forceChoice().model, forces);
        const int steps = 40;
        int64_t collisions = 0;
        for (int s = 0; s < steps; ++s) {
            const StepReport r = sim->step();
            collisions += r.pairCollisions + r.wallCollisions;
        }
        const ForceCounters c = sim->backend().forceCounters();
        EXPECT_GT(collisions, steps);  // collisions on most steps
        EXPECT_EQ(c.fullPasses, steps + 1);
        EXPECT_GT(c.refreshes, steps / 2);
        if (forces == ForceModel::NeighbourList) {
            EXPECT_LE(c.listBuilds, steps / 4);  // the skin lasts several steps
            EXPECT_LT(c.refreshedParticles, int64_t(steps) * scene.particleCount());
        }

        // The cached accelerations after a collision step equal a full pass over the same state.
        const ParticleState before = sim->state();
        sim->backend().kick(1.0);
        const ParticleState refreshed = sim->state();
        std::unique_ptr<Backend> fresh = makeTestBackend("cpu", Precision::Fp64);
        DeviceModel model = deviceModelOf(stepParametersOf(scene));
        model.forces = forces;
        fresh->setModel(model);
        fresh->setState(before);
        fresh->computeAccelerations();
        fresh->kick(1.0);
        const ParticleState full = fresh->state();
        double scale = 0, worst = 0;
        for (size_t i = 0; i < before.size(); ++i) scale = std::max(scale, std::sqrt(norm2(full.velocity[i] - before.velocity[i])));
        for (size_t i = 0; i < before.size(); ++i) worst = std::max(worst, std::sqrt(norm2(refreshed.velocity[i] - full.velocity[i])));
        EXPECT_LT(worst, 1e-12 * scale + 1e-14);
    }
}

// The list pass cuts the particles into one chunk per thread (src/cpu/verlet_list.h) from a few
// thousand particles on, and every particle still sums its pairs in one order: 1, 2 and 3 threads
// (one, two and three chunks, pairs across chunks evaluated in both) give the same bits, with
// collisions, wall hits and list rebuilds on the way.
TEST(NeighbourListCpu, SameStateOnOneTwoAndThreeThreads) {
    Scene scene = collidingGas(ForceModel::NeighbourList);
    scene.species[0].count = 5000;
    scene.box.size = {26, 24, 22};
    scene.species[0].sigma = 0.9;
    scene.interaction.restitution = 0.9;
    auto hashOf = [&](int threads) {
        auto sim = makeSimulation("cpu", scene, threads);
        int64_t collisions = 0;
        for (int s = 0; s < 60; ++s) {
            const StepReport r = sim->step();
            collisions += r.pairCollisions + r.wallCollisions;
        }
        EXPECT_GT(sim->backend().forceCounters().listBuilds, 1);
        EXPECT_GT(collisions, 60);
        return stateHash(sim->state());
    };
    const uint64_t one = hashOf(1);
    EXPECT_EQ(one, hashOf(2));
    EXPECT_EQ(one, hashOf(3));
    EXPECT_EQ(one, hashOf(1));
}

// The CPU's collision screen (its end-of-step list pass, kernels/collision_screen.h): a step with
// nothing near contact skips the stage, one with wall hits alone resolves them at once. The run equals
// the same scene with all pairs, whose stage searches everything every step: the same collision
// counts, wall pressure to 1e-9, states to 1e-9 (the force sums differ in order only).
TEST(NeighbourListCpu, TheCollisionScreenKeepsTheFullStagesResult) {
    auto liquid = [](ForceModel forces) {
        Scene scene;
        SpeciesDef a;
        a.count = 1500;
        a.radius = 0.42;
        scene.species = {a};
        scene.interaction.cutoff = 2.5;
        scene.interaction.forces = forces;
        const double side = std::cbrt(1500 / 0.7);
        scene.box.size = {side * 1.3, side, side / 1.3};
        scene.integrator.method = Method::Verlet;
        scene.integrator.dt = 2e-3;
        scene.thermostat.kind = ThermostatKind::None;
        scene.init.temperature = 2.0;
        scene.init.seed = 21;
        return scene;
    };
    auto lists = makeSimulation("cpu", liquid(ForceModel::NeighbourList));
    auto all = makeSimulation("cpu", liquid(ForceModel::AllPairs));
    int quiet = 0, wallsOnly = 0;
    int64_t walls = 0;
    for (int k = 0; k < 100; ++k) {
        const StepReport l = lists->step(), a = all->step();
        EXPECT_EQ(a.screen, StageScreen::Full);
        quiet += l.screen == StageScreen::Quiet ? 1 : 0;
        wallsOnly += l.screen == StageScreen::WallsOnly ? 1 : 0;
        EXPECT_EQ(l.pairCollisions, a.pairCollisions) << "step " << k;
        EXPECT_EQ(l.wallCollisions, a.wallCollisions) << "step " << k;
        walls += a.wallCollisions;
    }
    EXPECT_GT(quiet, 0);
    EXPECT_GT(wallsOnly, 0);
    EXPECT_GT(walls, 0);
    const ObservablesRow l = lists->observe(), a = all->observe();
    EXPECT_GT(a.pressureWall, 0);
    EXPECT_NEAR(l.pressureWall, a.pressureWall, 1e-9 * a.pressureWall);
    const ParticleState sl = lists->state(), sa = all->state();
    double worst = 0;
    for (size_t i = 0; i < sl.size(); ++i) worst = std::max(worst, std::sqrt(norm2(sl.position[i] - sa.position[i])));
    EXPECT_LT(worst, 1e-9 * lists->scene().box.size[0]);
}

// A live edit of the cutoff re-chooses the model, and the observables rows say which one ran.
TEST(NeighbourListCpu, LiveCutoffEditsSwitchTheModel) {
    Scene scene = collidingGas(ForceModel::Auto);
    scene.species[0].count = 4000;
    scene.box.size = {18, 18, 18};
    scene.init.placement = Placement::Lattice;
    auto sim = makeSimulation("cpu", scene);
    EXPECT_EQ(sim->forceChoice().model, ForceModel::NeighbourList) << sim->forceChoice().reason;
    sim->step();
    StepParameters p = stepParametersOf(sim->scene());
    std::ostringstream csv;
    writeObservablesRow(csv, sim->observe());
    p.interaction.cutoff = 0;
    sim->setStepParameters(p);
    EXPECT_EQ(sim->forceChoice().model, ForceModel::AllPairs);
    sim->step();
    writeObservablesRow(csv, sim->observe());
    p.interaction.cutoff = 2.0;
    sim->setStepParameters(p);
    EXPECT_EQ(sim->forceChoice().model, ForceModel::NeighbourList);
    sim->step();
    writeObservablesRow(csv, sim->observe());
    const std::string header = observablesHeader(sim->scene());
    EXPECT_EQ(header.substr(header.rfind(',')), ",forces");
    std::vector<std::string> last;
    std::istringstream lines(csv.str());
    for (std::string line; std::getline(lines, line);) last.push_back(line.substr(line.rfind(',') + 1));
    EXPECT_EQ(last, (std::vector<std::string>{"neighbour_list", "all_pairs", "neighbour_list"}));
}
