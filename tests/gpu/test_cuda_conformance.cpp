// CUDA backend against the CPU oracle on N = 1234 particles (not a multiple of a block): every
// integrator in fp64 without collisions (positions to 1e-9 relative after 20 steps), collision
// counts and energies with collisions, fp32 tolerances, identical initial states, and the same
// observables machinery (energies, health, speed statistics).
#include <cmath>

#include "gpu_fixture.h"
#include "initial_conditions.h"
#include "simulation.h"

using namespace corebox;

namespace {

Scene ljGas(Method method, Precision precision) {
    Scene scene;
    SpeciesDef a, b;
    a.name = "A";
    a.count = 734;
    a.radius = 0.1;  // never touch: LJ repulsion keeps pairs beyond 0.8 sigma
    b.name = "B";
    b.count = 500;
    b.radius = 0.1;
    b.mass = 2.0;
    b.sigma = 1.1;
    scene.species = {a, b};
    scene.interaction.mixing = {{1.0, 0.6}, {0.6, 1.0}};
    scene.interaction.cutoff = 2.5;
    scene.box.size = {16, 16, 16};
    scene.integrator.method = method;
    scene.integrator.dt = 1e-3;
    scene.integrator.precision = precision;
    scene.thermostat.kind = ThermostatKind::None;
    scene.init.seed = 11;
    return scene;
}

Scene hardSphereMix(Precision precision) {
    Scene scene;
    SpeciesDef a, b;
    a.name = "A";
    a.count = 834;
    a.epsilon = 0;
    b.name = "B";
    b.count = 400;
    b.epsilon = 0;
    b.radius = 0.6;
    b.mass = 3.0;
    scene.species = {a, b};
    scene.box.size = {15, 15, 15};
    scene.interaction.restitution = 0.9;
    scene.box.wallRestitution = 0.8;
    scene.interaction.gravity = {0, 0, -0.5};
    scene.integrator.method = Method::Rk4;
    scene.integrator.dt = 4e-3;
    scene.integrator.precision = precision;
    scene.thermostat.kind = ThermostatKind::None;
    scene.init.temperature = 2.0;
    scene.init.placement = Placement::Random;
    return scene;
}

std::unique_ptr<Backend> backendFor(const std::string& name, Precision p) {
    if (name == "cpu") return makeCpuBackend(CpuBackendOptions{p, 0});
    return makeCudaBackend(CudaBackendOptions{p, 0});
}

Simulation simulate(const Scene& scene, const std::string& backend, int steps, int64_t* pairs = nullptr, int64_t* walls = nullptr) {
    Simulation sim(scene, backendFor(backend, scene.integrator.precision), makeInitialState(scene));
    for (int s = 0; s < steps; ++s) {
        const StepReport r = sim.step();
        if (pairs) *pairs += r.pairCollisions;
        if (walls) *walls += r.wallCollisions;
    }
    return sim;
}

double maxRelativeDifference(const ParticleState& a, const ParticleState& b, double scale) {
    double worst = 0;
    for (size_t i = 0; i < a.size(); ++i) {
        worst = std::max(worst, std::sqrt(norm2(a.position[i] - b.position[i])) / scale);
    }
    return worst;
}

}  // namespace

TEST(CudaConformance, SameSeedGivesTheSameInitialStateOnCpuAndCuda) {
    COREBOX_REQUIRE_GPU();
    // Each backend starts its own simulation from the scene (as `corebox run` does); what each holds
    // must be the same state, bit for bit, and a different seed a different one (so equality here
    // is not the comparison of a state with itself).
    const Scene scene = ljGas(Method::Rk4, Precision::Fp64);
    Scene reseeded = scene;
    reseeded.init.seed = scene.init.seed + 1;
    const ParticleState a = simulate(scene, "cpu", 0).state();
    const ParticleState g = simulate(scene, "cuda", 0).state();
    const ParticleState other = simulate(reseeded, "cuda", 0).state();
    ASSERT_EQ(a.size(), g.size());
    size_t differentFromOtherSeed = 0;
    for (size_t i = 0; i < a.size(); ++i) {
        for (int k = 0; k < 3; ++k) {
            ASSERT_EQ(a.position[i][k], g.position[i][k]) << "particle " << i;
            ASSERT_EQ(a.velocity[i][k], g.velocity[i][k]) << "particle " << i;
            differentFromOtherSeed += a.velocity[i][k] != other.velocity[i][k];
        }
        ASSERT_EQ(a.species[i], g.species[i]);
    }
    EXPECT_GT(differentFromOtherSeed, a.size());
}

TEST(CudaConformance, EveryMethodMatchesTheCpuInFp64WithoutCollisions) {
    COREBOX_REQUIRE_GPU();
    for (Method m : {Method::Euler, Method::Rk2, Method::Rk4, Method::Dp5, Method::Hairer10, Method::Verlet}) {
        const Scene scene = ljGas(m, Precision::Fp64);
        int64_t cpuPairs = 0, cudaPairs = 0;
        Simulation cpu = simulate(scene, "cpu", 20, &cpuPairs);
        Simulation cuda = simulate(scene, "cuda", 20, &cudaPairs);
        EXPECT_EQ(cpuPairs, 0);
        EXPECT_EQ(cudaPairs, 0);
        const double diff = maxRelativeDifference(cpu.state(), cuda.state(), 16.0);
        RecordProperty(std::string("fp64_") + methodName(m), std::to_string(diff));
        EXPECT_LT(diff, 1e-9) << methodName(m);
        const ObservablesRow a = cpu.observe(), b = cuda.observe();
        EXPECT_NEAR(a.kinetic, b.kinetic, 1e-9 * std::fabs(a.kinetic)) << methodName(m);
        EXPECT_NEAR(a.potential, b.potential, 1e-9 * std::fabs(a.potential)) << methodName(m);
    }
}

TEST(CudaConformance, AdaptiveDp5TakesTheSameSteps) {
    COREBOX_REQUIRE_GPU();
    Scene scene = ljGas(Method::Dp5, Precision::Fp64);
    scene.integrator.adaptive = true;
    scene.integrator.tolerance = 1e-7;
    scene.integrator.dt = 1e-2;
    Simulation cpu = simulate(scene, "cpu", 10);
    Simulation cuda = simulate(scene, "cuda", 10);
    EXPECT_NEAR(cpu.time(), cuda.time(), 1e-12);
    EXPECT_LT(maxRelativeDifference(cpu.state(), cuda.state(), 16.0), 1e-9);
}

TEST(CudaConformance, CollisionsGiveTheSameCountsAndEnergies) {
    COREBOX_REQUIRE_GPU();
    const Scene scene = hardSphereMix(Precision::Fp64);
    int64_t cpuPairs = 0, cpuWalls = 0, cudaPairs = 0, cudaWalls = 0;
    Simulation cpu = simulate(scene, "cpu", 20, &cpuPairs, &cpuWalls);
    Simulation cuda = simulate(scene, "cuda", 20, &cudaPairs, &cudaWalls);
    RecordProperty("pair_collisions_cpu", std::to_string(cpuPairs));
    RecordProperty("pair_collisions_cuda", std::to_string(cudaPairs));
    EXPECT_GT(cpuPairs, 100);
    EXPECT_GT(cpuWalls, 10);
    // Same algorithm, same order of events: the same collisions, and energies to round-off.
    EXPECT_EQ(cpuPairs, cudaPairs);
    EXPECT_EQ(cpuWalls, cudaWalls);
    const ObservablesRow a = cpu.observe(), b = cuda.observe();
    EXPECT_NEAR(a.kinetic, b.kinetic, 1e-9 * a.kinetic);
    EXPECT_NEAR(a.potential, b.potential, 1e-9 * std::fabs(a.potential));
    EXPECT_NEAR(a.dissipated, b.dissipated, 1e-9 * a.dissipated);
    EXPECT_LT(maxRelativeDifference(cpu.state(), cuda.state(), 15.0), 1e-9);
}

TEST(CudaConformance, Fp32StaysWithinItsTolerance) {
    COREBOX_REQUIRE_GPU();
    // fp32 against the fp64 CPU oracle: 20 steps of an LJ gas keep positions within 1e-5 of the
    // box (float round-off ~1e-7 per operation, amplified by the dynamics) and the collision
    // scene's kinetic energy within 1e-3.
    const Scene gas32 = ljGas(Method::Rk4, Precision::Fp32), gas64 = ljGas(Method::Rk4, Precision::Fp64);
    Simulation oracle = simulate(gas64, "cpu", 20);
    Simulation cuda32 = simulate(gas32, "cuda", 20);
    Simulation cpu32 = simulate(gas32, "cpu", 20);
    const double gpuDiff = maxRelativeDifference(oracle.state(), cuda32.state(), 16.0);
    RecordProperty("fp32_position_difference", std::to_string(gpuDiff));
    EXPECT_LT(gpuDiff, 1e-5);
    EXPECT_LT(maxRelativeDifference(cpu32.state(), cuda32.state(), 16.0), 1e-5);
    int64_t pairs32 = 0, pairs64 = 0;
    Simulation hs64 = simulate(hardSphereMix(Precision::Fp64), "cpu", 20, &pairs64);
    Simulation hs32 = simulate(hardSphereMix(Precision::Fp32), "cuda", 20, &pairs32);
    EXPECT_NEAR(double(pairs32), double(pairs64), 0.05 * double(pairs64));
    EXPECT_NEAR(hs32.observe().kinetic, hs64.observe().kinetic, 1e-3 * hs64.observe().kinetic);
}

TEST(CudaConformance, HealthFindsTheSameBrokenParticlesAsTheCpu) {
    COREBOX_REQUIRE_GPU();
    const Scene scene = hardSphereMix(Precision::Fp64);
    Simulation cpu = simulate(scene, "cpu", 5);
    Simulation cuda = simulate(scene, "cuda", 5);
    // Break three particles the same way on both: one non-finite, two outside the box.
    ParticleState broken = cpu.state();
    broken.velocity[3].y = std::nan("");
    broken.position[100].z = scene.box.size[2] + 1.0;
    broken.position[1000].x = -0.5;
    for (Simulation* sim : {&cpu, &cuda}) sim->backend().setState(broken);
    const HealthReport a = cpu.backend().health(), b = cuda.backend().health();
    EXPECT_EQ(a.nonFinite, 1);
    EXPECT_EQ(a.outsideBox, 2);
    EXPECT_EQ(a.examples, (std::vector<int64_t>{3, 100, 1000}));
    EXPECT_EQ(b.nonFinite, a.nonFinite);
    EXPECT_EQ(b.outsideBox, a.outsideBox);
    EXPECT_EQ(b.examples, a.examples);
}

TEST(CudaConformance, SpeedStatisticsAgreeWithTheCpu) {
    COREBOX_REQUIRE_GPU();
    const Scene scene = hardSphereMix(Precision::Fp64);
    Simulation cpu = simulate(scene, "cpu", 5);
    Simulation cuda = simulate(scene, "cuda", 5);
    for (int species : {-1, 0, 1}) {
        SpeedRequest request;
        request.species = species;
        request.temperature = 2.0;
        const SpeedStatistics a = cpu.speedStatistics(request), b = cuda.speedStatistics(request);
        EXPECT_GT(a.count, 0);
        EXPECT_EQ(a.count, b.count);
        EXPECT_EQ(a.histogram, b.histogram) << "species " << species;
        EXPECT_NEAR(a.ksStatistic, b.ksStatistic, 1e-9) << "species " << species;
    }
}
