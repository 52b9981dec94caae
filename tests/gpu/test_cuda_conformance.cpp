// CUDA backend against the CPU oracle on N = 1234 particles (not a multiple of a block, nor of the
// GPU counts) and N = 4099: every integrator in fp64 without collisions (positions to 1e-9 relative
// after 20 steps), collision counts and energies with collisions, fp32 tolerances, identical initial
// states, the thermostats, and the same observables machinery (energies, health, speed statistics);
// for several GPUs, the one-GPU collisions and the same bytes from every exchange. Every body runs
// on one GPU and on P = 2, 3, 4 and 8 GPUs with each exchange (named Gpus/CudaConformance.Test/p2_dta
// and so on); a configuration needing more GPUs than are visible skips with a message.
#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>

#include "errors.h"
#include "gpu_fixture.h"
#include "initial_conditions.h"
#include "simulation.h"
#include "vocabulary.h"

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

// The GPU configuration of a test instance.
struct GpuConfig {
    int gpus = 1;
    Exchange exchange = Exchange::Auto;
};

std::vector<GpuConfig> gpuConfigs() {
    std::vector<GpuConfig> out{{1, Exchange::Auto}};
    for (int p : {2, 3, 4, 8})
        for (Exchange e : {Exchange::Dts, Exchange::Dta, Exchange::Da, Exchange::Nccl}) out.push_back({p, e});
    return out;
}

std::string configName(const ::testing::TestParamInfo<GpuConfig>& info) {
    if (info.param.gpus == 1) return "p1";
    return "p" + std::to_string(info.param.gpus) + "_" + exchangeName(info.param.exchange);
}

GpuConfig g_config;  // the running instance's, read by backendFor("cuda")

std::unique_ptr<Backend> backendFor(const std::string& name, Precision p, GpuConfig config = g_config) {
    if (name == "cpu") return makeCpuBackend(CpuBackendOptions{p, 0});
    CudaBackendOptions options;
    options.precision = p;
    options.gpus = config.gpus;
    options.exchange = config.exchange;
    return makeCudaBackend(options);
}

Simulation simulate(const Scene& scene, const std::string& backend, int steps, int64_t* pairs = nullptr, int64_t* walls = nullptr,
                    GpuConfig config = g_config) {
    Simulation sim(scene, backendFor(backend, scene.integrator.precision, config), makeInitialState(scene));
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

// The CPU oracle's state after `steps` steps, computed once per scene (each instance compares with it).
struct OracleRun {
    ParticleState state;
    ObservablesRow row;
    int64_t pairs = 0, walls = 0;
    double time = 0;
};
const OracleRun& cpuOracle(const std::string& key, const Scene& scene, int steps) {
    static std::map<std::string, OracleRun> cache;
    auto found = cache.find(key);
    if (found != cache.end()) return found->second;
    OracleRun run;
    Simulation sim = simulate(scene, "cpu", steps, &run.pairs, &run.walls);
    run.state = sim.state();
    run.row = sim.observe();
    run.time = sim.time();
    return cache.emplace(key, std::move(run)).first->second;
}

Scene withCount(Scene scene, int64_t n) {
    // Keep the species' proportions and the number density: the box grows with the cube root.
    const int64_t n0 = scene.particleCount();
    scene.species[1].count = n * scene.species[1].count / n0;
    scene.species[0].count = n - scene.species[1].count;
    const double grow = std::cbrt(double(n) / double(n0));
    for (double& l : scene.box.size) l *= grow;
    return scene;
}

class CudaConformance : public ::testing::TestWithParam<GpuConfig> {
protected:
    void SetUp() override {
        COREBOX_REQUIRE_GPUS(GetParam().gpus);
        g_config = GetParam();
    }
    void TearDown() override { g_config = GpuConfig{}; }
};

}  // namespace

INSTANTIATE_TEST_SUITE_P(Gpus, CudaConformance, ::testing::ValuesIn(gpuConfigs()), configName);

TEST_P(CudaConformance, SameSeedGivesTheSameInitialStateOnCpuAndCuda) {
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

TEST_P(CudaConformance, EveryMethodMatchesTheCpuInFp64WithoutCollisions) {
    for (int64_t n : {1234, 4099}) {
        for (const Term<Method>& method : methodTable()) {  // every method, the compositions of Verlet included
            const Method m = method.value;
            const Scene scene = withCount(ljGas(m, Precision::Fp64), n);
            const OracleRun& cpu = cpuOracle(std::string("lj_") + methodName(m) + "_" + std::to_string(n), scene, 20);
            int64_t cudaPairs = 0;
            Simulation cuda = simulate(scene, "cuda", 20, &cudaPairs);
            EXPECT_EQ(cpu.pairs, 0);
            EXPECT_EQ(cudaPairs, 0);
            const double diff = maxRelativeDifference(cpu.state, cuda.state(), scene.box.size[0]);
            RecordProperty(std::string("fp64_") + methodName(m) + "_" + std::to_string(n), std::to_string(diff));
            EXPECT_LT(diff, 1e-9) << methodName(m) << ", N = " << n;
            const ObservablesRow& a = cpu.row;
            const ObservablesRow b = cuda.observe();
            EXPECT_NEAR(a.kinetic, b.kinetic, 1e-9 * std::fabs(a.kinetic)) << methodName(m) << ", N = " << n;
            EXPECT_NEAR(a.potential, b.potential, 1e-9 * std::fabs(a.potential)) << methodName(m) << ", N = " << n;
        }
    }
}

TEST_P(CudaConformance, AdaptiveDp5TakesTheSameSteps) {
    Scene scene = ljGas(Method::Dp5, Precision::Fp64);
    scene.integrator.adaptive = true;
    scene.integrator.tolerance = 1e-7;
    scene.integrator.dt = 1e-2;
    const OracleRun& cpu = cpuOracle("lj_adaptive_dp5", scene, 10);
    Simulation cuda = simulate(scene, "cuda", 10);
    EXPECT_NEAR(cpu.time, cuda.time(), 1e-12);
    EXPECT_LT(maxRelativeDifference(cpu.state, cuda.state(), 16.0), 1e-9);
}

TEST_P(CudaConformance, CollisionsGiveTheSameCountsAndEnergies) {
    const Scene scene = hardSphereMix(Precision::Fp64);
    const OracleRun& cpu = cpuOracle("hard_sphere_mix", scene, 20);
    int64_t cudaPairs = 0, cudaWalls = 0;
    Simulation cuda = simulate(scene, "cuda", 20, &cudaPairs, &cudaWalls);
    RecordProperty("pair_collisions_cpu", std::to_string(cpu.pairs));
    RecordProperty("pair_collisions_cuda", std::to_string(cudaPairs));
    EXPECT_GT(cpu.pairs, 100);
    EXPECT_GT(cpu.walls, 10);
    // Same algorithm, same order of events: the same collisions, and energies to round-off.
    EXPECT_EQ(cpu.pairs, cudaPairs);
    EXPECT_EQ(cpu.walls, cudaWalls);
    const ObservablesRow& a = cpu.row;
    const ObservablesRow b = cuda.observe();
    EXPECT_NEAR(a.kinetic, b.kinetic, 1e-9 * a.kinetic);
    EXPECT_NEAR(a.potential, b.potential, 1e-9 * std::fabs(a.potential));
    EXPECT_NEAR(a.dissipated, b.dissipated, 1e-9 * a.dissipated);
    EXPECT_LT(maxRelativeDifference(cpu.state, cuda.state(), 15.0), 1e-9);
}

TEST_P(CudaConformance, ContactLogAndSpeciesFieldsMatchTheCpu) {
    // The library's contacts come from the contact log: the same impacts in the same order (round,
    // particle) on every backend, with the same normals, impulses and times; and each species' own
    // field (added to gravity) acts the same.
    Scene scene = hardSphereMix(Precision::Fp64);
    scene.species[1].acceleration = {0.3, 0.0, 0.8};
    Simulation cpu(scene, backendFor("cpu", Precision::Fp64), makeInitialState(scene));
    Simulation cuda(scene, backendFor("cuda", Precision::Fp64), makeInitialState(scene));
    cpu.backend().setContactLog(true, 0.0);
    cuda.backend().setContactLog(true, 0.0);
    size_t records = 0;
    std::vector<double> impulses;
    for (int step = 0; step < 20; ++step) {
        const StepReport a = cpu.step(), b = cuda.step();
        const std::vector<ContactRecord> x = cpu.backend().contactLog(), y = cuda.backend().contactLog();
        ASSERT_EQ(int64_t(x.size()), a.pairCollisions + a.wallCollisions) << "step " << step;
        ASSERT_EQ(x.size(), y.size()) << "step " << step;
        ASSERT_EQ(b.pairCollisions + b.wallCollisions, int64_t(y.size()));
        for (size_t k = 0; k < x.size(); ++k) {
            ASSERT_EQ(x[k].a, y[k].a) << "step " << step << " record " << k;
            ASSERT_EQ(x[k].b, y[k].b);
            ASSERT_EQ(x[k].round, y[k].round);
            EXPECT_NEAR(x[k].time, y[k].time, 1e-9);
            EXPECT_NEAR(x[k].impulse, y[k].impulse, 1e-9 * (1 + std::fabs(x[k].impulse)));
            EXPECT_NEAR(x[k].speed, y[k].speed, 1e-9 * (1 + x[k].speed));
            for (int c = 0; c < 3; ++c) EXPECT_NEAR(x[k].normal[c], y[k].normal[c], 1e-9);
            impulses.push_back(std::fabs(x[k].impulse));
        }
        records += x.size();
    }
    EXPECT_GT(records, 100u);
    EXPECT_LT(maxRelativeDifference(cpu.state(), cuda.state(), 15.0), 1e-9);
    EXPECT_NEAR(cpu.observe().potential, cuda.observe().potential, 1e-9 * std::fabs(cpu.observe().potential));
    // A threshold (the median impulse so far): both record only impacts at or above it, and the same
    // ones, apart from any within rounding (1e-9) of it, where the backends' impulses may fall on either side.
    std::nth_element(impulses.begin(), impulses.begin() + impulses.size() / 2, impulses.end());
    const double threshold = impulses[impulses.size() / 2];
    cpu.backend().setContactLog(true, threshold);
    cuda.backend().setContactLog(true, threshold);
    size_t strong = 0;
    for (int step = 0; step < 20; ++step) {
        cpu.step();
        cuda.step();
        auto clear = [&](const std::vector<ContactRecord>& log) {
            std::vector<ContactRecord> out;
            for (const ContactRecord& c : log) {
                EXPECT_GE(std::fabs(c.impulse), threshold) << "step " << step;
                if (std::fabs(c.impulse) > threshold * (1 + 1e-9)) out.push_back(c);
            }
            return out;
        };
        const std::vector<ContactRecord> x = clear(cpu.backend().contactLog()), y = clear(cuda.backend().contactLog());
        ASSERT_EQ(x.size(), y.size()) << "step " << step;
        for (size_t k = 0; k < x.size(); ++k) {
            ASSERT_EQ(x[k].a, y[k].a) << "step " << step << " record " << k;
            ASSERT_EQ(x[k].b, y[k].b);
            EXPECT_NEAR(x[k].impulse, y[k].impulse, 1e-9 * (1 + std::fabs(x[k].impulse)));
        }
        strong += x.size();
    }
    EXPECT_GT(strong, 20u);
    // Off again: nothing recorded.
    cuda.backend().setContactLog(false, 0.0);
    cuda.step();
    EXPECT_TRUE(cuda.backend().contactLog().empty());
}

TEST_P(CudaConformance, SeveralGpusGiveTheOneGpuCollisionsAndExchangesTheSameBytes) {
    // With P GPUs the collision stage runs on the gathered state: the one-GPU counts and losses. The
    // exchanges move the same bytes, so for one P every method gives the same state bit for bit
    // (compared with DT-S, the simplest).
    if (GetParam().gpus == 1) GTEST_SKIP() << "compares several GPUs with one";
    for (Precision p : {Precision::Fp64, Precision::Fp32}) {
        const Scene scene = hardSphereMix(p);
        int64_t onePairs = 0, oneWalls = 0, pairs = 0, walls = 0, refPairs = 0, refWalls = 0;
        Simulation one = simulate(scene, "cuda", 20, &onePairs, &oneWalls, GpuConfig{1, Exchange::Auto});
        Simulation many = simulate(scene, "cuda", 20, &pairs, &walls);
        Simulation reference = simulate(scene, "cuda", 20, &refPairs, &refWalls, GpuConfig{GetParam().gpus, Exchange::Dts});
        EXPECT_EQ(pairs, onePairs) << precisionName(p);
        EXPECT_EQ(walls, oneWalls) << precisionName(p);
        EXPECT_NEAR(many.observe().dissipated, one.observe().dissipated, 1e-9 * one.observe().dissipated) << precisionName(p);
        const ParticleState a = many.state(), b = reference.state();
        size_t differing = 0;
        for (size_t i = 0; i < a.size(); ++i)
            for (int k = 0; k < 3; ++k) differing += a.position[i][k] != b.position[i][k] || a.velocity[i][k] != b.velocity[i][k];
        EXPECT_EQ(differing, 0u) << precisionName(p) << ": " << exchangeName(GetParam().exchange) << " against dts";
        EXPECT_EQ(pairs, refPairs);
    }
}

TEST_P(CudaConformance, SeveralGpusExchangeTheSameBytesUnderPairForces) {
    // As above with every position read by a force pass (the LJ gas, all pairs and a cutoff run as
    // lists, RK4 and Verlet): for one P, every exchange method gives DT-S's state bit for bit, and with
    // all pairs one GPU's (force_kernels.cu: launchForces). DA reads
    // the positions in place and computes every pair even where lists are asked for (useLists), so it
    // is held to the all-pairs runs only.
    if (GetParam().gpus == 1) GTEST_SKIP() << "compares exchange methods: several GPUs";
    for (Method m : {Method::Rk4, Method::Verlet}) {
        for (ForceModel forces : {ForceModel::AllPairs, ForceModel::NeighbourList}) {
            if (forces == ForceModel::NeighbourList && GetParam().exchange == Exchange::Da) continue;
            Scene scene = ljGas(m, Precision::Fp64);
            scene.interaction.forces = forces;
            const ParticleState a = simulate(scene, "cuda", 20).state();
            const ParticleState b = simulate(scene, "cuda", 20, nullptr, nullptr, GpuConfig{GetParam().gpus, Exchange::Dts}).state();
            auto differing = [](const ParticleState& x, const ParticleState& y) {
                size_t count = 0;
                for (size_t i = 0; i < x.size(); ++i)
                    for (int k = 0; k < 3; ++k) count += x.position[i][k] != y.position[i][k] || x.velocity[i][k] != y.velocity[i][k];
                return count;
            };
            EXPECT_EQ(differing(a, b), 0u) << methodName(m) << ", " << forceModelName(forces) << ": " << exchangeName(GetParam().exchange)
                                           << " against dts";
            // All pairs with at most 2048 rows a GPU: the pass a block a row, the one GPU's bits too.
            if (forces == ForceModel::AllPairs) {
                const ParticleState one = simulate(scene, "cuda", 20, nullptr, nullptr, GpuConfig{1, Exchange::Auto}).state();
                EXPECT_EQ(differing(a, one), 0u) << methodName(m) << ": " << exchangeName(GetParam().exchange) << " against one GPU";
            }
        }
    }
}

TEST_P(CudaConformance, ThermostatsMatchTheCpu) {
    // The thermostats draw from the counter-based generator (the same numbers on every backend) and
    // scale with the kinetic energy summed on the device: with P GPUs as with one, the CPU's state
    // and the energy the thermostat gave, to round-off, heating the gas from 1 to 2 over 60 steps.
    for (ThermostatKind kind : {ThermostatKind::Bussi, ThermostatKind::Rescale}) {
        Scene scene = ljGas(Method::Verlet, Precision::Fp64);
        scene.init.temperature = 1.0;
        scene.thermostat.kind = kind;
        scene.thermostat.temperature = 2.0;
        scene.thermostat.tau = 0.02;
        const OracleRun& cpu = cpuOracle(std::string("lj_thermostat_") + thermostatName(kind), scene, 60);
        Simulation cuda = simulate(scene, "cuda", 60);
        const ObservablesRow& a = cpu.row;
        const ObservablesRow b = cuda.observe();
        EXPECT_GT(a.thermostat, 0.1 * a.kinetic) << thermostatName(kind) << ": the thermostat heated the gas";
        EXPECT_NEAR(a.thermostat, b.thermostat, 1e-9 * a.kinetic) << thermostatName(kind);
        EXPECT_NEAR(a.kinetic, b.kinetic, 1e-9 * a.kinetic) << thermostatName(kind);
        EXPECT_LT(maxRelativeDifference(cpu.state, cuda.state(), scene.box.size[0]), 1e-9) << thermostatName(kind);
    }
}

TEST_P(CudaConformance, FewerParticlesThanGpusStepAsOneGpu) {
    // P - 1 particles on P GPUs: the last slice is empty, and every per-slice launch must skip it (a
    // grid of no blocks is a launch error); P + 1 leaves empty slices from four GPUs on (chunks of 2).
    // Same bits as one GPU, for Verlet and RK4.
    if (GetParam().gpus == 1) GTEST_SKIP() << "needs an empty slice: several GPUs";
    for (int count : {GetParam().gpus - 1, GetParam().gpus + 1}) {
        for (Method m : {Method::Verlet, Method::Rk4}) {
            Scene scene = ljGas(m, Precision::Fp64);
            scene.species.resize(1);
            scene.species[0].count = count;
            scene.interaction.mixing = {{1.0}};
            scene.box.size = {3, 3, 3};
            scene.init.temperature = 1.0;
            const ParticleState one =
                simulate(scene, "cuda", 10, nullptr, nullptr, GpuConfig{1, Exchange::Auto}).state();
            const ParticleState many = simulate(scene, "cuda", 10).state();
            ASSERT_EQ(many.size(), one.size());
            for (size_t i = 0; i < one.size(); ++i)
                for (int k = 0; k < 3; ++k)
                    EXPECT_EQ(many.position[i][k], one.position[i][k]) << methodName(m) << ", particle " << i;
        }
    }
}

TEST_P(CudaConformance, Fp32StaysWithinItsTolerance) {
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

TEST_P(CudaConformance, HealthFindsTheSameBrokenParticlesAsTheCpu) {
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

TEST_P(CudaConformance, SpeedStatisticsAgreeWithTheCpu) {
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

TEST(CudaDevices, AskingForMoreGpusThanExistNamesTheDevicesFound) {
    COREBOX_REQUIRE_GPU();
    CudaBackendOptions options;
    options.gpus = cudaDeviceCount() + 1;
    try {
        makeCudaBackend(options);
        FAIL() << "no error for " << options.gpus << " GPUs";
    } catch (const DeviceError& e) {
        const std::string message = e.what();
        EXPECT_NE(message.find("found"), std::string::npos) << message;
        EXPECT_NE(message.find(cudaDeviceDescription(0)), std::string::npos) << message;
    }
}

TEST(CudaDevices, WithoutPeerAccessDaIsRefusedAndTheCopiesMatchTheCpu) {
    // Every pair taken to lack peer access (CudaBackendOptions::peerAccessDenied: corebox's decisions,
    // not host-staged copies, since peer access enabled earlier in the process stays): DA refused with a
    // message naming the pairs and the methods that work; auto never DA, where with peer access it
    // would be on eight GPUs; DT-S, DT-A, NCCL and auto give the CPU's state to 1e-9 and one another's
    // bits.
    COREBOX_REQUIRE_GPUS(2);
    EXPECT_EQ(fastestExchange(8, true), Exchange::Da) << "the case below would be vacuous";
    EXPECT_NE(fastestExchange(8, false), Exchange::Da);
    EXPECT_NE(fastestExchange(2, false), Exchange::Da);
    auto options = [](Exchange exchange) {
        CudaBackendOptions o;
        o.precision = Precision::Fp64;
        o.gpus = 2;
        o.exchange = exchange;
        o.peerAccessDenied = true;
        return o;
    };
    try {
        makeCudaBackend(options(Exchange::Da));
        FAIL() << "DA accepted without peer access";
    } catch (const DeviceError& e) {
        const std::string message = e.what();
        EXPECT_NE(message.find("no peer access between GPUs 0 -> 1, 1 -> 0"), std::string::npos) << message;
        EXPECT_NE(message.find("use --exchange dta, dts or nccl"), std::string::npos) << message;
    }
    const Scene scene = withCount(ljGas(Method::Rk4, Precision::Fp64), 1234);  // EveryMethodMatches...'s scene and key
    const OracleRun& cpu = cpuOracle("lj_rk4_1234", scene, 20);
    ParticleState first;
    for (Exchange e : {Exchange::Dts, Exchange::Dta, Exchange::Nccl, Exchange::Auto}) {
        Simulation sim(scene, makeCudaBackend(options(e)), makeInitialState(scene));
        EXPECT_EQ(sim.backend().deviceName().find("da exchange"), std::string::npos) << sim.backend().deviceName();
        for (int s = 0; s < 20; ++s) sim.step();
        const ParticleState state = sim.state();
        EXPECT_LT(maxRelativeDifference(cpu.state, state, scene.box.size[0]), 1e-9) << exchangeName(e);
        if (first.size() == 0) first = state;
        size_t differing = 0;
        for (size_t i = 0; i < state.size(); ++i)
            for (int k = 0; k < 3; ++k) differing += state.position[i][k] != first.position[i][k] || state.velocity[i][k] != first.velocity[i][k];
        EXPECT_EQ(differing, 0u) << exchangeName(e) << " against dts";
    }
}
