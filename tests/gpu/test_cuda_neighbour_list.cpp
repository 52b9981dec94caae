// Neighbour-list forces on the GPU (kernels/neighbour_list_kernels.cu) against the CPU oracle and
// against the GPU's own all-pairs tiles: fp64 positions within 1e-9 relative over 20 Verlet steps,
// energies too; the same state hash run to run. Skips, visibly, without a CUDA device.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <tuple>
#include <vector>
#include <memory>
#include <string>

#include "gpu_fixture.h"
#include "initial_conditions.h"
#include "simulation.h"
#include "state_hash.h"

using namespace corebox;

namespace {

// A two-species LJ liquid (different sigma) with a cutoff, N = 4099 (not a multiple of a block), at
// number density 0.7 in a non-cubic box, from a lattice, hot enough that lists are rebuilt.
Scene liquid(ForceModel forces, Precision precision) {
    Scene scene;
    SpeciesDef a, b;
    a.name = "A";
    a.count = 2899;
    a.radius = 0.1;
    b.name = "B";
    b.count = 1200;
    b.radius = 0.1;
    b.mass = 2.0;
    b.sigma = 1.15;
    scene.species = {a, b};
    scene.interaction.mixing = {{1.0, 0.6}, {0.6, 1.0}};
    scene.interaction.cutoff = 2.5;
    scene.interaction.forces = forces;
    const double volume = 4099 / 0.7;
    scene.box.size = {std::cbrt(volume) * 1.3, std::cbrt(volume), std::cbrt(volume) / 1.3};
    scene.integrator.method = Method::Verlet;
    scene.integrator.dt = 2e-3;
    scene.integrator.precision = precision;
    scene.thermostat.kind = ThermostatKind::None;
    scene.init.temperature = 2.0;
    scene.init.seed = 21;
    return scene;
}

std::unique_ptr<Backend> backendFor(const std::string& name, Precision p) {
    if (name == "cpu") return makeCpuBackend(CpuBackendOptions{p, 0});
    CudaBackendOptions options;
    options.precision = p;
    options.gpus = 1;
    return makeCudaBackend(options);
}

struct SimRun {
    ParticleState state;
    ObservablesRow row;
    ForceChoice choice;
    ForceCounters counters;
};

SimRun simulate(const Scene& scene, const std::string& backend, int steps) {
    Simulation sim(scene, backendFor(backend, scene.integrator.precision), makeInitialState(scene));
    for (int s = 0; s < steps; ++s) sim.step();
    return SimRun{sim.state(), sim.observe(), sim.forceChoice(), sim.backend().forceCounters()};
}

double maxRelativeDifference(const ParticleState& a, const ParticleState& b, double scale) {
    double worst = 0;
    for (size_t i = 0; i < a.size(); ++i) worst = std::max(worst, std::sqrt(norm2(a.position[i] - b.position[i])) / scale);
    return worst;
}

void expectSameRun(const SimRun& a, const SimRun& b, double boxScale) {
    EXPECT_LT(maxRelativeDifference(a.state, b.state, boxScale), 1e-9);
    EXPECT_NEAR(a.row.kinetic, b.row.kinetic, 1e-9 * std::fabs(a.row.kinetic));
    EXPECT_NEAR(a.row.potential, b.row.potential, 1e-9 * std::fabs(a.row.potential));
    EXPECT_NEAR(a.row.pressureVirial, b.row.pressureVirial, 1e-9 * std::fabs(a.row.pressureVirial));
}

}  // namespace

TEST(CudaNeighbourList, ListsMatchTheCpuAndAllPairsOverTwentySteps) {
    COREBOX_REQUIRE_GPU();
    const Scene lists = liquid(ForceModel::NeighbourList, Precision::Fp64);
    const double scale = lists.box.size[0];
    const SimRun gpu = simulate(lists, "cuda", 20);
    ASSERT_EQ(gpu.choice.model, ForceModel::NeighbourList) << gpu.choice.reason;
    EXPECT_GE(gpu.counters.listBuilds, 1);
    const SimRun cpu = simulate(lists, "cpu", 20);
    expectSameRun(cpu, gpu, scale);
    const SimRun gpuAllPairs = simulate(liquid(ForceModel::AllPairs, Precision::Fp64), "cuda", 20);
    EXPECT_EQ(gpuAllPairs.counters.listBuilds, 0);
    expectSameRun(gpuAllPairs, gpu, scale);
}

// B as hard spheres (epsilon 0) with cores that meet: collisions on most steps. The rows that read a
// moved particle are summed again (the same kernel, in the same order), never a second full pass, and
// the run still follows the CPU's.
TEST(CudaNeighbourList, ACollisionStepCostsNoSecondForcePass) {
    COREBOX_REQUIRE_GPU();
    Scene scene = liquid(ForceModel::NeighbourList, Precision::Fp64);
    scene.species[1].epsilon = 0;
    scene.species[1].radius = 0.5;
    const int steps = 60;
    Simulation sim(scene, backendFor("cuda", Precision::Fp64), makeInitialState(scene));
    int64_t collisions = 0;
    for (int s = 0; s < steps; ++s) collisions += sim.step().pairCollisions;
    const ForceCounters c = sim.backend().forceCounters();
    EXPECT_GT(collisions, 20);
    EXPECT_GT(c.refreshes, 20);
    EXPECT_LE(c.fullPasses, steps + 1 + c.listBuilds) << "a full pass beyond one per step and one per list rebuild";
    const SimRun gpu{sim.state(), sim.observe(), sim.forceChoice(), c};
    expectSameRun(simulate(scene, "cpu", steps), gpu, scene.box.size[0]);
}

// The same with all pairs: the moved particles sum again and everyone else exchanges their old pair
// forces for new ones (O(N M)), never a second full pass; the run follows the CPU's, which does the same.
TEST(CudaAllPairs, ACollisionStepCostsNoSecondForcePass) {
    COREBOX_REQUIRE_GPU();
    Scene scene = liquid(ForceModel::AllPairs, Precision::Fp64);
    scene.species[1].epsilon = 0;
    scene.species[1].radius = 0.5;
    const int steps = 60;
    Simulation sim(scene, backendFor("cuda", Precision::Fp64), makeInitialState(scene));
    int64_t collisions = 0;
    for (int s = 0; s < steps; ++s) collisions += sim.step().pairCollisions;
    const ForceCounters c = sim.backend().forceCounters();
    ASSERT_EQ(sim.forceChoice().model, ForceModel::AllPairs);
    EXPECT_GT(collisions, 20);
    EXPECT_GT(c.refreshes, 20);
    EXPECT_LE(c.fullPasses, steps + 1) << "a full pass beyond one per step";
    const SimRun gpu{sim.state(), sim.observe(), sim.forceChoice(), c};
    expectSameRun(simulate(scene, "cpu", steps), gpu, scene.box.size[0]);
}

// The collision screen (CudaDevice::screenStage): the list pass at the end of each Verlet step tells
// whether anything is near contact. Steps with nothing near skip the stage, steps with only wall hits
// resolve them at once (resolveWallImpacts); the run is the CPU's to 1e-9, with the same collision
// counts and wall pressure (the CPU screens too; NeighbourListCpu.TheCollisionScreenKeepsTheFullStagesResult
// holds it to a stage that searches everything). About one particle a step hits a wall here (Poisson),
// so both kinds of screened step occur.
TEST(CudaNeighbourList, TheCollisionScreenSkipsQuietStepsAndKeepsTheCpuResult) {
    COREBOX_REQUIRE_GPU();
    Scene scene = liquid(ForceModel::NeighbourList, Precision::Fp64);
    for (SpeciesDef& s : scene.species) s.radius = 0.42;
    const int steps = 100;
    Simulation gpu(scene, backendFor("cuda", Precision::Fp64), makeInitialState(scene));
    Simulation cpu(scene, backendFor("cpu", Precision::Fp64), makeInitialState(scene));
    int quiet = 0, wallsOnly = 0, cpuScreened = 0;
    int64_t gpuPairs = 0, gpuWalls = 0, cpuPairs = 0, cpuWalls = 0;
    for (int k = 0; k < steps; ++k) {
        const StepReport g = gpu.step(), c = cpu.step();
        quiet += g.screen == StageScreen::Quiet ? 1 : 0;
        wallsOnly += g.screen == StageScreen::WallsOnly ? 1 : 0;
        cpuScreened += c.screen != StageScreen::Full ? 1 : 0;
        gpuPairs += g.pairCollisions;
        gpuWalls += g.wallCollisions;
        cpuPairs += c.pairCollisions;
        cpuWalls += c.wallCollisions;
    }
    RecordProperty("quiet_steps", quiet);
    RecordProperty("walls_only_steps", wallsOnly);
    EXPECT_GT(quiet, 0);
    EXPECT_GT(wallsOnly, 0);
    EXPECT_GT(cpuScreened, 0);
    RecordProperty("cpu_screened_steps", cpuScreened);
    EXPECT_GT(gpuWalls, 0);
    EXPECT_EQ(gpuPairs, cpuPairs);
    EXPECT_EQ(gpuWalls, cpuWalls);
    const ObservablesRow gpuRow = gpu.observe(), cpuRow = cpu.observe();
    // The wall impulses of the walls-only stage reach the pressure as the rounds' do.
    EXPECT_GT(cpuRow.pressureWall, 0);
    EXPECT_NEAR(gpuRow.pressureWall, cpuRow.pressureWall, 1e-9 * cpuRow.pressureWall);
    EXPECT_NEAR(gpuRow.pressureWallCentre, cpuRow.pressureWallCentre, 1e-9 * std::fabs(cpuRow.pressureWallCentre) + 1e-12);
    expectSameRun(SimRun{cpu.state(), cpuRow, cpu.forceChoice(), {}}, SimRun{gpu.state(), gpuRow, gpu.forceChoice(), {}}, scene.box.size[0]);
}

// The one-wait step (src/cuda/cuda_device.h): the fused launches and the stage decided on the device
// give the bits of the step as separate operations, with each kind of stage met: quiet, walls only,
// whole (hard B cores meet), lists rebuilt after a forecast (a thin skin); and the snapshot the
// kick-drift kernel takes is the state before the step.
TEST(CudaNeighbourList, TheOneWaitStepGivesTheBitsOfSeparateOperations) {
    COREBOX_REQUIRE_GPU();
    auto run = [](const Scene& scene, bool fused, int steps) {
        CudaBackendOptions options;
        options.precision = scene.integrator.precision;
        options.fusedSteps = fused;
        Simulation sim(scene, makeCudaBackend(options), makeInitialState(scene));
        std::map<StageScreen, int> screens;
        int64_t pairs = 0, walls = 0;
        for (int k = 0; k < steps; ++k) {
            const StepReport r = sim.step();
            ++screens[r.screen];
            pairs += r.pairCollisions;
            walls += r.wallCollisions;
        }
        const ObservablesRow row = sim.observe();
        return std::make_tuple(stateHash(sim.state()), stateHash(sim.backend().snapshot()), screens, pairs, walls, row.kinetic,
                               row.pressureWall, sim.backend().forceCounters().listBuilds);
    };
    for (Precision p : {Precision::Fp32, Precision::Fp64}) {
        Scene screened = liquid(ForceModel::NeighbourList, p);
        for (SpeciesDef& s : screened.species) s.radius = 0.42;
        screened.interaction.skin = 0.1;
        Scene colliding = liquid(ForceModel::NeighbourList, p);
        colliding.species[1].epsilon = 0;
        colliding.species[1].radius = 0.5;
        for (const Scene& scene : {screened, colliding}) {
            const auto fused = run(scene, true, 120), separate = run(scene, false, 120);
            EXPECT_EQ(std::get<0>(fused), std::get<0>(separate)) << precisionName(p) << ": the state";
            EXPECT_EQ(std::get<1>(fused), std::get<1>(separate)) << precisionName(p) << ": the snapshot";
            EXPECT_EQ(std::get<2>(fused), std::get<2>(separate)) << precisionName(p) << ": the screens";
            EXPECT_EQ(std::get<3>(fused), std::get<3>(separate));
            EXPECT_EQ(std::get<4>(fused), std::get<4>(separate));
            EXPECT_EQ(std::get<5>(fused), std::get<5>(separate)) << precisionName(p) << ": the kinetic energy";
            EXPECT_EQ(std::get<6>(fused), std::get<6>(separate)) << precisionName(p) << ": the wall pressure";
            EXPECT_GE(std::get<7>(fused), 3) << "the lists were rebuilt";
        }
        auto fused = run(screened, true, 120);
        EXPECT_GT(std::get<2>(fused)[StageScreen::Quiet], 0);
        EXPECT_GT(std::get<2>(fused)[StageScreen::WallsOnly], 0);
        EXPECT_GT(std::get<4>(fused), 0) << "walls were hit";
        EXPECT_GT(std::get<3>(run(colliding, true, 120)), 0) << "cores met";
    }
}

// Running ahead (cuda_device.h) moves when the next step's kick-drift and force pass run, not what they
// compute: the same states, snapshots, screens, collisions and observables as the same fused steps
// without it, with observables and state reads between the steps (which must see the step just
// taken, not the one running ahead), in both precisions, with walls only, with cores that meet (Full
// stages, where the gate stays shut) and with a thermostat that rescales every step (each step that
// ran ahead forgotten). Lists may be built a step early (on the forecast's hint, by the step that runs
// ahead), which changes no bit: a listed pair beyond the cutoff adds an exact zero. Then again with the
// lists built ahead given too few columns, so that each such step is done again after the wait.
TEST(CudaNeighbourList, RunningAheadGivesTheBitsOfTheStepAfterTheWait) {
    COREBOX_REQUIRE_GPU();
    auto run = [](const Scene& scene, bool ahead, int steps, int aheadListColumns = 0) {
        CudaBackendOptions options;
        options.precision = scene.integrator.precision;
        options.runAhead = ahead;
        options.aheadListColumns = aheadListColumns;
        Simulation sim(scene, makeCudaBackend(options), makeInitialState(scene));
        std::map<StageScreen, int> screens;
        int64_t pairs = 0, walls = 0;
        std::vector<uint64_t> midway;
        std::vector<double> energies;
        for (int k = 0; k < steps; ++k) {
            const StepReport r = sim.step();
            ++screens[r.screen];
            pairs += r.pairCollisions;
            walls += r.wallCollisions;
            if (k % 10 == 9) {
                const ObservablesRow row = sim.observe();
                energies.push_back(row.total());
                midway.push_back(stateHash(sim.state()));
            }
        }
        return std::make_tuple(stateHash(sim.state()), stateHash(sim.backend().snapshot()), screens, pairs, walls, energies, midway,
                               sim.backend().forceCounters().listBuilds, sim.backend().forceCounters().stepsRunAhead);
    };
    for (Precision p : {Precision::Fp32, Precision::Fp64}) {
        Scene screened = liquid(ForceModel::NeighbourList, p);
        for (SpeciesDef& s : screened.species) s.radius = 0.42;
        Scene colliding = liquid(ForceModel::NeighbourList, p);
        colliding.species[1].epsilon = 0;
        colliding.species[1].radius = 0.5;
        screened.interaction.skin = 0.3;  // fewer rebuilds, which no step runs ahead of
        Scene thermostatted = screened;
        thermostatted.thermostat.kind = ThermostatKind::Bussi;
        thermostatted.thermostat.temperature = 1.0;
        thermostatted.thermostat.tau = 0.1;
        int scene = 0;
        for (const Scene& s : {screened, colliding, thermostatted, screened}) {
            const bool overflowing = scene == 3;
            const auto ahead = run(s, true, 120, overflowing ? 8 : 0), after = run(s, false, 120);
            const std::string what = std::string(precisionName(p)) + ", scene " + std::to_string(scene);
            EXPECT_EQ(std::get<0>(ahead), std::get<0>(after)) << what << ": the state";
            EXPECT_EQ(std::get<1>(ahead), std::get<1>(after)) << what << ": the snapshot";
            EXPECT_EQ(std::get<2>(ahead), std::get<2>(after)) << what << ": the screens";
            EXPECT_EQ(std::get<3>(ahead), std::get<3>(after)) << what << ": pair collisions";
            EXPECT_EQ(std::get<4>(ahead), std::get<4>(after)) << what << ": wall collisions";
            EXPECT_EQ(std::get<5>(ahead), std::get<5>(after)) << what << ": the energies observed";
            EXPECT_EQ(std::get<6>(ahead), std::get<6>(after)) << what << ": the states read midway";
            // Early builds, and those of steps that ran ahead but were not taken, add to the count.
            EXPECT_GE(std::get<7>(ahead), std::get<7>(after)) << what << ": list builds";
            EXPECT_LE(std::get<7>(ahead), 2 * std::get<7>(after) + 2) << what << ": list builds";
            EXPECT_EQ(std::get<8>(after), 0) << what;
            if (scene == 0 || scene == 3) {  // 21 of 120 on an H200: the rebuilds, the wall contacts and the observations between steps stop the others
                EXPECT_GE(std::get<8>(ahead), 12) << what << ": steps ran ahead";
            }
            if (scene == 2) {
                EXPECT_EQ(std::get<8>(ahead), 0) << what << ": the thermostat changes every step's velocities";
            }
            ++scene;
        }
    }
}

TEST(CudaNeighbourList, RebuildsKeepTheCpuResult) {
    COREBOX_REQUIRE_GPU();
    Scene scene = liquid(ForceModel::NeighbourList, Precision::Fp64);
    scene.interaction.skin = 0.05;  // rebuilt every few steps
    const SimRun gpu = simulate(scene, "cuda", 20);
    const SimRun cpu = simulate(scene, "cpu", 20);
    EXPECT_GT(gpu.counters.listBuilds, 2);
    EXPECT_GT(cpu.counters.listBuilds, 2);
    expectSameRun(cpu, gpu, scene.box.size[0]);
}

TEST(CudaNeighbourList, SameStateRunToRunInBothPrecisions) {
    COREBOX_REQUIRE_GPU();
    for (Precision p : {Precision::Fp32, Precision::Fp64}) {
        const Scene scene = liquid(ForceModel::NeighbourList, p);
        EXPECT_EQ(stateHash(simulate(scene, "cuda", 30).state), stateHash(simulate(scene, "cuda", 30).state)) << precisionName(p);
    }
}

TEST(CudaNeighbourList, Fp32ListsStayCloseToTheFp64Oracle) {
    COREBOX_REQUIRE_GPU();
    const Scene scene = liquid(ForceModel::NeighbourList, Precision::Fp32);
    Scene oracle = scene;
    oracle.integrator.precision = Precision::Fp64;
    const SimRun gpu = simulate(scene, "cuda", 20);
    const SimRun cpu = simulate(oracle, "cpu", 20);
    EXPECT_LT(maxRelativeDifference(cpu.state, gpu.state, scene.box.size[0]), 1e-5);
    EXPECT_NEAR(gpu.row.potential, cpu.row.potential, 1e-4 * std::fabs(cpu.row.potential));
}
