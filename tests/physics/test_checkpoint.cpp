// Checkpoint and restart (checkpoint.h): a run stopped at step S, written to a file, read back and
// continued is bit-identical to the run that never stopped, for every integrator, with collisions,
// a thermostat and a live edit before the checkpoint; and a checkpoint that is truncated, damaged or
// not a checkpoint at all is refused with a message. Every test runs on each backend present.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>

#include "checkpoint.h"
#include "errors.h"
#include "initial_conditions.h"
#include "physics_fixtures.h"
#include "scene_io.h"

using namespace corebox;
using namespace corebox::testing;

namespace {

// Two species, A with LJ forces and B hard spheres, whose cores collide (restitution 0.8), walls
// (0.9) and a Bussi thermostat.
Scene restartScene(Method method, bool adaptive, ForceModel forces = ForceModel::Auto) {
    Scene scene;
    SpeciesDef a, b;
    a.name = "A";
    a.count = 70;
    a.radius = 0.56;  // cores beyond the LJ minimum (2^(1/6) sigma): they meet at T = 1.5
    b.name = "B";
    b.count = 50;
    b.radius = 0.6;
    b.mass = 2;
    b.epsilon = 0;  // B meets everything as a hard sphere: collisions from the first steps
    scene.species = {a, b};
    scene.box.size = {6, 6, 6};
    scene.box.wallRestitution = 0.9;
    scene.interaction.cutoff = 2.5;
    scene.interaction.restitution = 0.8;
    scene.interaction.forces = forces;
    scene.integrator.method = method;
    scene.integrator.dt = method == Method::Hairer10 ? 4e-3 : 2e-3;
    scene.integrator.adaptive = adaptive;
    scene.integrator.tolerance = 1e-7;
    scene.thermostat.kind = ThermostatKind::Bussi;
    scene.thermostat.temperature = 1.5;
    scene.init.temperature = 1.5;
    return scene;
}

std::string scratchPath(const std::string& name) {
    return (std::filesystem::temp_directory_path() / ("corebox_checkpoint_" + name)).string();
}

class Restart : public OnEveryBackend {};

}  // namespace

INSTANTIATE_TEST_SUITE_P(Backends, Restart, ::testing::ValuesIn(backendNames()), backendInstanceName);

TEST_P(Restart, ARestartedRunIsBitIdenticalToOneThatNeverStopped) {
    struct Case {
        Method method;
        bool adaptive;
        const char* name;
        ForceModel forces = ForceModel::Auto;
    };
    // The list cases: the restarted run builds its lists afresh at the checkpoint's positions, the
    // uninterrupted one still uses lists built steps earlier (other pairs, another walk).
    for (const Case& c : {Case{Method::Euler, false, "euler"}, Case{Method::Rk2, false, "rk2"}, Case{Method::Rk4, false, "rk4"},
                          Case{Method::Dp5, false, "dp5"}, Case{Method::Dp5, true, "dp5 adaptive"},
                          Case{Method::Hairer10, false, "hairer10"}, Case{Method::Verlet, false, "verlet"},
                          Case{Method::Verlet, false, "verlet, neighbour lists", ForceModel::NeighbourList},
                          Case{Method::Rk4, false, "rk4, neighbour lists", ForceModel::NeighbourList},
                          Case{Method::Verlet, false, "verlet, all pairs", ForceModel::AllPairs}}) {
        SCOPED_TRACE(c.name);
        Scene scene = restartScene(c.method, c.adaptive, c.forces);
        if (c.forces == ForceModel::AllPairs) {
            // Few enough moved particles per step for the CPU's all-pairs update after collisions
            // (A not a force pass's bits: the checkpoint carries it).
            scene.species[0].count = 700;
            scene.box.size = {12, 12, 12};
        }
        // Lists: long enough for particles to change cells and for rebuilds (skin 0.3) before the checkpoint.
        const int warmup = c.forces == ForceModel::NeighbourList ? 400 : 15;
        const ParticleState initial = makeInitialState(scene);
        auto whole = std::make_unique<Simulation>(scene, makeTestBackend(backendName(), Precision::Fp64), initial);
        auto first = std::make_unique<Simulation>(scene, makeTestBackend(backendName(), Precision::Fp64), initial);
        int64_t collisions = 0;
        // A live edit of the potential (work re-bases the conserved sum) and an observables row
        // before the checkpoint; the checkpoint between two rows carries the counters and the
        // pressure window.
        for (Simulation* sim : {whole.get(), first.get()}) {
            for (int s = 0; s < warmup; ++s) collisions += sim->step().pairCollisions;
            StepParameters p = stepParametersOf(sim->scene());
            p.interaction.gravity = {0, 0, -0.5};
            sim->setStepParameters(p);
            (void)sim->observe();
            for (int s = 0; s < 10; ++s) collisions += sim->step().pairCollisions;
        }
        EXPECT_GT(collisions, 0) << "the scene must exercise the collision stage";
        const std::string path = scratchPath(std::string(backendName()) + "_" + c.name);
        writeCheckpoint(path, first->checkpoint());
        first.reset();
        const SimulationCheckpoint read = readCheckpoint(path);
        Simulation restarted(parseScene(read.sceneToml, path), makeTestBackend(backendName(), Precision::Fp64), read);
        std::filesystem::remove(path);
        EXPECT_EQ(restarted.stepIndex(), whole->stepIndex());
        for (int s = 0; s < 25; ++s) {
            const StepReport a = whole->step(), b = restarted.step();
            ASSERT_EQ(a.dt, b.dt) << "step " << s;
            ASSERT_EQ(a.pairCollisions, b.pairCollisions) << "step " << s;
        }
        const ParticleState sa = whole->state(), sb = restarted.state();
        ASSERT_EQ(sa.size(), sb.size());
        for (size_t i = 0; i < sa.size(); ++i) {
            for (int k = 0; k < 3; ++k) {
                ASSERT_EQ(sa.position[i][k], sb.position[i][k]) << "particle " << i;
                ASSERT_EQ(sa.velocity[i][k], sb.velocity[i][k]) << "particle " << i;
            }
        }
        const ObservablesRow ra = whole->observe(), rb = restarted.observe();
        EXPECT_EQ(ra.time, rb.time);
        EXPECT_EQ(ra.kinetic, rb.kinetic);
        EXPECT_EQ(ra.potential, rb.potential);
        EXPECT_EQ(ra.dissipated, rb.dissipated);
        EXPECT_EQ(ra.thermostat, rb.thermostat);
        EXPECT_EQ(ra.collisionsPair, rb.collisionsPair);
        EXPECT_EQ(ra.collisionsWall, rb.collisionsWall);
        EXPECT_EQ(ra.pressureWall, rb.pressureWall);
        EXPECT_EQ(ra.pressureVirial, rb.pressureVirial);
        EXPECT_EQ(whole->parameterWork(), restarted.parameterWork());
    }
}

namespace {

// 300 balls dropped into a narrow box: a settled pile after 3 s.
Scene pileScene() {
    Scene scene;
    SpeciesDef ball;
    ball.count = 300;
    ball.radius = 0.5;
    ball.epsilon = 0;
    scene.species = {ball};
    scene.box.size = {8, 20, 8};
    scene.box.wallRestitution = 0.5;
    scene.interaction.gravity = {0, -9.81, 0};
    scene.interaction.restitution = 0.5;
    scene.integrator.method = Method::Verlet;
    scene.integrator.dt = 1.0 / 240;
    scene.thermostat.kind = ThermostatKind::None;
    scene.init.temperature = 0.1;
    return scene;
}

// Steps `a` and `b` on together and expects the same sweeps every step and the same bits at the end.
void expectTheSameRun(Simulation& a, Simulation& b, int steps) {
    for (int s = 0; s < steps; ++s) {
        const StepReport ra = a.step(), rb = b.step();
        ASSERT_EQ(ra.contactSweeps, rb.contactSweeps) << "step " << s;
    }
    const ParticleState sa = a.state(), sb = b.state();
    for (size_t i = 0; i < sa.size(); ++i) {
        for (int k = 0; k < 3; ++k) {
            ASSERT_EQ(sa.position[i][k], sb.position[i][k]) << "particle " << i;
            ASSERT_EQ(sa.velocity[i][k], sb.velocity[i][k]) << "particle " << i;
        }
    }
    EXPECT_EQ(a.observe().dissipated, b.observe().dissipated);
}

}  // namespace

TEST_P(Restart, ARestartedPileIsBitIdenticalWithItsWarmStart) {
    // A settled pile: a backend that warm-starts its contact relaxation (contact_relaxation.h) holds
    // the last step's impulses, and the checkpoint carries them, so the restarted run starts its next
    // relaxation where the uninterrupted one does. The CUDA backend also keeps its contacts' colours
    // between fresh colourings (cuda_collisions.cpp: every 4th step afresh): 721 steps, so that the
    // first step after the restart keeps them, from the checkpoint.
    const Scene scene = pileScene();
    const ParticleState initial = makeInitialState(scene);
    auto whole = std::make_unique<Simulation>(scene, makeTestBackend(backendName(), Precision::Fp64), initial);
    auto first = std::make_unique<Simulation>(scene, makeTestBackend(backendName(), Precision::Fp64), initial);
    for (int s = 0; s < 721; ++s) {
        whole->step();
        first->step();
    }
    const SimulationCheckpoint kept = first->checkpoint();
    EXPECT_GT(kept.contactImpulses.size(), 300u) << "a settled pile rests on its contacts";
    if (std::string(backendName()) == "cuda") {
        EXPECT_EQ(kept.contactColours.size(), kept.contactImpulses.size());
    }
    const std::string path = scratchPath(std::string(backendName()) + "_pile");
    writeCheckpoint(path, kept);
    first.reset();
    const SimulationCheckpoint read = readCheckpoint(path);
    std::filesystem::remove(path);
    ASSERT_EQ(read.contactImpulses.size(), kept.contactImpulses.size());
    EXPECT_EQ(read.contactColours, kept.contactColours);
    Simulation restarted(parseScene(read.sceneToml, path), makeTestBackend(backendName(), Precision::Fp64), read);
    expectTheSameRun(*whole, restarted, 60);
}

TEST_P(Restart, ColoursThatAreNoColouringAreDropped) {
    // Colours in a checkpoint that cannot be its contacts' (two contacts of a particle sharing one, or a
    // colour beyond the 64 there are) are dropped, not swept with (a race on the GPU): the restart colours
    // afresh, as one from a checkpoint that carries no colours does, bit for bit.
    const Scene scene = pileScene();
    Simulation sim(scene, makeTestBackend(backendName(), Precision::Fp64), makeInitialState(scene));
    for (int s = 0; s < 721; ++s) sim.step();
    SimulationCheckpoint colourless = sim.checkpoint();
    ASSERT_GT(colourless.contactImpulses.size(), 300u);
    colourless.contactColours.clear();
    for (uint8_t colour : {uint8_t(0), uint8_t(200)}) {
        SimulationCheckpoint bad = colourless;
        bad.contactColours.assign(bad.contactImpulses.size(), colour);
        Simulation a(scene, makeTestBackend(backendName(), Precision::Fp64), bad);
        Simulation b(scene, makeTestBackend(backendName(), Precision::Fp64), colourless);
        SCOPED_TRACE("every colour " + std::to_string(int(colour)));
        expectTheSameRun(a, b, 8);
    }
}

namespace {

std::string fileBytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

void writeBytes(const std::string& path, const std::string& bytes) { std::ofstream(path, std::ios::binary) << bytes; }

}  // namespace

TEST(CheckpointFile, ContactColoursRoundTripAndVersion3FilesAreStillRead) {
    // Version 4 appends the contact impulses' colours (a count, 0 or one an impulse, and a byte each)
    // after the impulses; a version 3 file ends with the impulses and reads back with no colours.
    SimulationCheckpoint c;
    c.sceneToml = "[box]\nsize = [4, 4, 4]\n";
    c.step = 7;
    c.state.resize(3);
    c.contactImpulses = {ContactWarmStart{0, 1, 0.5}, ContactWarmStart{1, -3, 0.25}};
    c.contactColours = {2, 5};
    const std::string path = scratchPath("colours");
    writeCheckpoint(path, c);
    SimulationCheckpoint read = readCheckpoint(path);
    ASSERT_EQ(read.contactImpulses.size(), 2u);
    EXPECT_EQ(read.contactImpulses[1].partner, -3);
    EXPECT_EQ(read.contactColours, c.contactColours);

    // The same file as version 3 wrote it: no colours' count and colours, the version field 3.
    std::string bytes = fileBytes(path);
    const size_t magic = std::string("corebox checkpoint\n").size();
    std::string v3 = bytes.substr(0, bytes.size() - sizeof(uint64_t) - sizeof(uint64_t) - c.contactColours.size());
    const uint32_t three = 3;
    std::memcpy(&v3[magic], &three, sizeof three);
    const uint64_t hash = checkpointChecksum(v3);
    v3.append(reinterpret_cast<const char*>(&hash), sizeof hash);
    writeBytes(path, v3);
    read = readCheckpoint(path);
    EXPECT_EQ(read.contactImpulses.size(), 2u);
    EXPECT_TRUE(read.contactColours.empty());

    // A colours' count that is neither 0 nor one an impulse is refused by the reader and the writer.
    std::string wrong = bytes.substr(0, bytes.size() - sizeof(uint64_t));
    const uint64_t three64 = 3;
    std::memcpy(&wrong[wrong.size() - c.contactColours.size() - sizeof(uint64_t)], &three64, sizeof three64);
    wrong.push_back('\x01');
    const uint64_t wrongHash = checkpointChecksum(wrong);
    wrong.append(reinterpret_cast<const char*>(&wrongHash), sizeof wrongHash);
    writeBytes(path, wrong);
    try {
        (void)readCheckpoint(path);
        ADD_FAILURE() << "a colours' count of 3 for 2 impulses was read";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("announces 3 contact colours for 2 contact impulses"), std::string::npos)
            << e.what();
    }
    c.contactColours.push_back(1);
    EXPECT_THROW(writeCheckpoint(path, c), std::invalid_argument);
    std::filesystem::remove(path);
    std::filesystem::remove(path + ".prev");
}

TEST_P(Restart, TruncatedDamagedAndForeignFilesAreRefused) {
    const Scene scene = restartScene(Method::Verlet, false);
    Simulation sim(scene, makeTestBackend(backendName(), Precision::Fp64), makeInitialState(scene));
    sim.step();
    const std::string path = scratchPath(std::string(backendName()) + "_bad");
    writeCheckpoint(path, sim.checkpoint());
    const auto size = std::filesystem::file_size(path);
    auto refusal = [&](const std::string& file) -> std::string {
        try {
            (void)readCheckpoint(file);
        } catch (const InputError& e) {
            return e.what();
        }
        return "";
    };
    EXPECT_EQ(refusal(path), "");
    // Writing again keeps the previous checkpoint beside the new one.
    writeCheckpoint(path, sim.checkpoint());
    EXPECT_TRUE(std::filesystem::exists(path + ".prev"));
    std::filesystem::resize_file(path, size - 100);
    EXPECT_NE(refusal(path).find("truncated"), std::string::npos) << refusal(path);
    std::filesystem::resize_file(path, 10);
    EXPECT_NE(refusal(path).find("not a corebox checkpoint"), std::string::npos) << refusal(path);
    {
        std::fstream f(path + ".prev", std::ios::in | std::ios::out | std::ios::binary);
        f.seekp(std::streamoff(size / 2));
        f.put('\x55');
    }
    EXPECT_NE(refusal(path + ".prev").find("damaged"), std::string::npos) << refusal(path + ".prev");
    {
        std::ofstream f(path);
        f << "[box]\nsize = [1, 1, 1]\n";
    }
    EXPECT_NE(refusal(path).find("not a corebox checkpoint"), std::string::npos) << refusal(path);
    EXPECT_NE(refusal(path + ".missing").find("cannot read checkpoint"), std::string::npos);
    std::filesystem::remove(path);
    std::filesystem::remove(path + ".prev");
}
