// A small scene with collisions, walls, gravity, a thermostat and every observable, run on one GPU and
// on two with each exchange:
// the workload compute-sanitizer's memcheck and racecheck inspect (ctest gpu_memcheck and
// gpu_racecheck run this test under them).
#include <array>
#include <vector>

#include "gpu_fixture.h"
#include "initial_conditions.h"
#include "simulation.h"

using namespace corebox;

namespace {

Scene smallScene() {
    Scene scene;
    SpeciesDef a, b;
    a.name = "A";
    a.count = 150;
    a.radius = 0.5;
    b.name = "B";
    b.count = 77;
    b.radius = 0.6;
    b.mass = 2;
    scene.species = {a, b};
    scene.box.size = {9, 9, 9};
    scene.interaction.restitution = 0.9;
    scene.interaction.gravity = {0, 0, -1};
    scene.interaction.cutoff = 2.5;
    scene.integrator.method = Method::Dp5;
    scene.integrator.adaptive = true;
    scene.integrator.dt = 2e-3;
    scene.init.temperature = 2.0;
    return scene;
}

void runSmallScene(int gpus, Exchange exchange) {
    Scene scene = smallScene();
    for (Precision p : {Precision::Fp64, Precision::Fp32}) {
        scene.integrator.precision = p;
        CudaBackendOptions options;
        options.precision = p;
        options.gpus = gpus;
        options.exchange = exchange;
        Simulation sim(scene, makeCudaBackend(options), makeInitialState(scene));
        int64_t collisions = 0;
        for (int s = 0; s < 30; ++s) collisions += sim.step().pairCollisions;
        sim.observe();
        SpeedRequest request;
        sim.speedStatistics(request);
        sim.backend().computeAccelerations();
        sim.backend().finish();
        EXPECT_GT(collisions, 0);
        // The health kernel's reporting path too: one particle pushed out of the box.
        ParticleState broken = sim.state();
        broken.position[7].x = -1.0;
        sim.backend().setState(broken);
        const HealthReport health = sim.backend().health();
        EXPECT_EQ(health.outsideBox, 1);
        ASSERT_EQ(health.examples.size(), 1u);
        EXPECT_EQ(health.examples[0], 7);
    }
}

// `count` particles of one species (hard-core radius `radius`) in a box of `size`.
Scene oneSpecies(const char* name, int64_t count, double radius, std::array<double, 3> size) {
    Scene scene;
    SpeciesDef s;
    s.name = name;
    s.count = count;
    s.radius = radius;
    scene.species = {s};
    scene.box.size = size;
    return scene;
}

// `count` balls of radius 0.5 on a lattice in a box of `size`, dropped: hard cores only, restitution
// 0.5 on each other and on the walls, gravity, Verlet at 1/240.
Scene droppedBalls(int64_t count, std::array<double, 3> size) {
    Scene scene = oneSpecies("ball", count, 0.5, size);
    scene.species[0].epsilon = 0;
    scene.box.wallRestitution = 0.5;
    scene.interaction.restitution = 0.5;
    scene.interaction.gravity = {0, 0, -9.81};
    scene.integrator.method = Method::Verlet;
    scene.integrator.dt = 1.0 / 240.0;
    scene.init.temperature = 0.1;
    return scene;
}

// `scene` run for `steps` steps on one GPU in fp64, then in fp32 (with `options`): each run's sum of
// count(report).
template <class Count>
std::vector<int64_t> sumOverSteps(Scene scene, int steps, Count count, CudaBackendOptions options = {}) {
    std::vector<int64_t> sums;
    for (Precision p : {Precision::Fp64, Precision::Fp32}) {
        scene.integrator.precision = p;
        options.precision = p;
        Simulation sim(scene, makeCudaBackend(options), makeInitialState(scene));
        int64_t sum = 0;
        for (int s = 0; s < steps; ++s) sum += count(sim.step());
        sums.push_back(sum);
    }
    return sums;
}

}  // namespace

TEST(CudaSanitized, SmallSceneWithCollisions) {
    COREBOX_REQUIRE_GPU();
    runSmallScene(1, Exchange::Auto);
}

// A small pile: the contact phase's kernels, its relaxation in one cooperative launch among them
// (grid-wide barriers, a block reduction in shared memory).
TEST(CudaSanitized, ASmallPileRelaxedInOneLaunch) {
    COREBOX_REQUIRE_GPU();
    const Scene scene = droppedBalls(160, {4, 4, 12});  // packing fraction 0.44: the lattice's balls nearly touch
    for (int64_t sweeps : sumOverSteps(scene, 80, [](const StepReport& r) { return r.contactSweeps; })) EXPECT_GT(sweeps, 80);
}

// The impact rounds reading candidate rows (gpu_launch.h CandidateRows), made from the first step and
// again as the balls fall, some rows overflowed (4 slots: walked in the cells of the rows' build), from
// 5,000 balls here (the default: more than 32,768).
TEST(CudaSanitized, ImpactRoundsOnCandidateRows) {
    COREBOX_REQUIRE_GPU();
    const Scene scene = droppedBalls(5000, {16, 16, 36});
    CudaBackendOptions options;
    options.candidateRowsFrom = 0;
    options.candidateSlots = 4;
    for (int64_t rounds : sumOverSteps(
             scene, 48, [](const StepReport& r) { return r.rounds; }, options))
        EXPECT_GT(rounds, 96);
}

// RK4 with all pairs and hard cores: the step as one graph (cuda_rk_graph.cpp, launched from the third
// step), and impact rounds queued without their counts read, each round's rows read by a pass that
// takes its count on the device, with the tally, the contact count and the step check behind them.
TEST(CudaSanitized, AnRk4StepAsAGraphAndItsRoundsOnTheDevice) {
    COREBOX_REQUIRE_GPU();
    Scene scene = oneSpecies("LJ", 300, 0.56, {8.5, 8.5, 8.5});  // number density 0.49, as bench table1's
    scene.interaction.restitution = 0.8;
    scene.interaction.forces = ForceModel::AllPairs;
    scene.integrator.method = Method::Rk4;
    scene.integrator.dt = 1e-3;
    scene.thermostat.kind = ThermostatKind::None;
    scene.init.temperature = 1.5;
    for (int64_t impacts : sumOverSteps(scene, 60, [](const StepReport& r) { return r.pairCollisions; })) EXPECT_GT(impacts, 20);
}

// The same on two, four and eight GPUs with each exchange: peer copies, direct peer reads (the force
// kernel's DA path) and NCCL. NCCL is apart: its own start-up probes kernels for other architectures
// and so hits API errors of its own, which the memcheck run does not count against corebox
// (tests/gpu/sanitize.sh).
#define COREBOX_SANITIZED_ON(P, Name)                               \
    TEST(CudaSanitized, Name##PeerCopies) {                         \
        COREBOX_REQUIRE_GPUS(P);                                    \
        for (Exchange e : {Exchange::Dts, Exchange::Dta}) {         \
            SCOPED_TRACE(exchangeName(e));                          \
            runSmallScene(P, e);                                    \
        }                                                           \
    }                                                               \
    TEST(CudaSanitized, Name##DirectAccess) {                       \
        COREBOX_REQUIRE_GPUS(P);                                    \
        runSmallScene(P, Exchange::Da);                             \
    }                                                               \
    TEST(CudaSanitized, Name##Nccl) {                               \
        COREBOX_REQUIRE_GPUS(P);                                    \
        runSmallScene(P, Exchange::Nccl);                           \
    }

COREBOX_SANITIZED_ON(2, TwoGpus)
COREBOX_SANITIZED_ON(4, FourGpus)
COREBOX_SANITIZED_ON(8, EightGpus)
