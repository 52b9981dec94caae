// The collision stage of a pile on the GPU with its host waits taken out (CudaBackendOptions::fusedSteps,
// src/cuda/cuda_collisions.cpp): a listing's sweeps in one cooperative launch that checks its own
// residual on the schedule the host would (relaxListing, RelaxationPlan), and the impact rounds queued
// in batches gated on each round's count (runImpactRounds), give the bits of the sweeps launched a pair
// at a time with a read-back a batch and of the rounds one at a time, on one GPU and on two (where the
// stage runs on the first, on the gathered state), in fp32 and fp64, with the sweeps Gauss-Seidel in
// colours (a cooperative launch against a launch a colour) and Jacobi. And the same for a stage with pair
// forces (all pairs, RK4: each round's end-of-step accelerations from a pass that reads the round's
// count on the device), whose tally, contact count and step check come back with the rounds' wait.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include <cstdio>
#include <random>
#include <string>
#include <tuple>
#include <utility>

#include "collision_rounds.h"
#include "gpu_fixture.h"
#include "gpu_launch.h"
#include "initial_conditions.h"
#include "simulation.h"
#include "state_hash.h"
#include "vocabulary.h"

using namespace corebox;

namespace {

// 600 balls of radius 0.5 dropped from a lattice into a 6 x 6 x 40 box (z up), restitution 0.5, g =
// 9.81, dt = 1/240: by 1.5 s a pile some twenty layers deep, relaxed by many sweeps a step.
Scene deepPile(Precision precision) {
    Scene scene;
    scene.box.size = {6.0, 6.0, 40.0};
    scene.box.wallRestitution = 0.5;
    SpeciesDef ball;
    ball.name = "ball";
    ball.count = 600;
    ball.mass = 1.0;
    ball.radius = 0.5;
    ball.sigma = 1.0;
    ball.epsilon = 0.0;
    scene.species = {ball};
    scene.interaction.restitution = 0.5;
    scene.interaction.gravity = {0.0, 0.0, -9.81};
    scene.integrator.method = Method::Verlet;
    scene.integrator.dt = 1.0 / 240.0;
    scene.integrator.precision = precision;
    scene.thermostat.kind = ThermostatKind::None;
    scene.init.temperature = 0.1;
    scene.init.seed = 7;
    scene.init.placement = Placement::Lattice;
    return scene;
}

// What a run leaves for comparing two ways of running the impact rounds bit for bit: the state's hash,
// the impacts and rounds summed over its steps, the dissipated energy, and with the contact log on its
// records and an FNV-1a hash of them (particles and round).
struct ImpactOutcome {
    uint64_t hash = 0;
    int64_t pairs = 0, walls = 0, rounds = 0, records = 0, capHits = 0;
    int64_t slowAtEnd = 0;  // particles slower than 0.4 times the resting speed after the last step
    double dissipated = 0;
    uint64_t logHash = 1469598103934665603ull;
};

ImpactOutcome runImpactsFrom(const Scene& scene, const ParticleState& start, const CudaBackendOptions& options,
                             int steps, bool log) {
    Simulation sim(scene, makeCudaBackend(options), start);
    sim.backend().setContactLog(log, 0.0);
    ImpactOutcome o;
    for (int k = 0; k < steps; ++k) {
        const StepReport r = sim.step();
        o.pairs += r.pairCollisions;
        o.walls += r.wallCollisions;
        o.rounds += r.rounds;
        o.capHits += r.roundCapHit ? 1 : 0;
        for (const ContactRecord& c : sim.backend().contactLog()) {
            ++o.records;
            for (int64_t v : {c.a, c.b, int64_t(c.round)}) o.logHash = (o.logHash ^ uint64_t(v)) * 1099511628211ull;
        }
    }
    o.hash = stateHash(sim.state());
    o.dissipated = sim.observe().dissipated;
    const double resting = collisionSettingsFor(scene.interaction, scene.integrator.dt, 0.0).restingSpeed;
    for (const Vec3<double>& v : sim.state().velocity) o.slowAtEnd += norm2(v) < 0.16 * resting * resting ? 1 : 0;
    return o;
}

ImpactOutcome runImpacts(const Scene& scene, const CudaBackendOptions& options, int steps, bool log) {
    return runImpactsFrom(scene, makeInitialState(scene), options, steps, log);
}

// The same state, impacts, rounds and dissipation.
void expectSameImpacts(const ImpactOutcome& a, const ImpactOutcome& reference, const std::string& where) {
    EXPECT_EQ(a.hash, reference.hash) << where << ": the state";
    EXPECT_EQ(a.pairs, reference.pairs) << where << ": the pair impacts";
    EXPECT_EQ(a.walls, reference.walls) << where << ": the wall impacts";
    EXPECT_EQ(a.rounds, reference.rounds) << where << ": the rounds";
    EXPECT_EQ(a.capHits, reference.capHits) << where << ": the steps at the round cap";
    EXPECT_EQ(a.dissipated, reference.dissipated) << where << ": the dissipated energy";
}

// And the same contact log.
void expectSameLog(const ImpactOutcome& a, const ImpactOutcome& reference, const std::string& where) {
    EXPECT_EQ(a.records, reference.records) << where << ": the log's records";
    EXPECT_EQ(a.logHash, reference.logHash) << where << ": the log";
}

// Table 1's model (bench table1): `count` Lennard-Jones particles with hard cores of radius 0.56 at
// number density 0.5, all pairs, RK4, here with restitution 0.8 so that the impacts dissipate: at 1234,
// a dozen impacts a step in two or three rounds.
Scene ljWithCores(Precision precision, ForceModel forces, int64_t count = 1234) {
    Scene scene;
    SpeciesDef s;
    s.name = "LJ";
    s.count = count;
    s.radius = 0.56;
    scene.species = {s};
    const double box = std::cbrt(double(count) / 0.5);
    scene.box.size = {box, box, box};
    scene.interaction.restitution = 0.8;
    scene.interaction.forces = forces;
    if (forces == ForceModel::NeighbourList) scene.interaction.cutoff = 2.5;
    scene.integrator.method = Method::Rk4;
    scene.integrator.dt = 1e-3;
    scene.integrator.precision = precision;
    scene.thermostat.kind = ThermostatKind::None;
    scene.init.temperature = 1.5;
    scene.init.seed = 11;
    return scene;
}

}  // namespace

TEST(CudaContacts, AStageWithPairForcesWithoutHostWaitsGivesTheBitsOfTheHostDrivenOne) {
    COREBOX_REQUIRE_GPU();
    auto run = [](const Scene& scene, int gpus, bool fused) {
        CudaBackendOptions options;
        options.precision = scene.integrator.precision;
        options.gpus = gpus;
        options.fusedSteps = fused;
        Simulation sim(scene, makeCudaBackend(options), makeInitialState(scene));
        int64_t pairs = 0, walls = 0, rounds = 0, contacts = 0;
        double virial = 0;
        for (int k = 0; k < 200; ++k) {
            const StepReport r = sim.step();
            pairs += r.pairCollisions;
            walls += r.wallCollisions;
            rounds += r.rounds;
            contacts += r.contacts;
            virial += r.impulses.pairVirial;
        }
        const ObservablesRow row = sim.observe();
        return std::make_tuple(stateHash(sim.state()), pairs, walls, rounds, row.dissipated, row.kinetic, contacts, virial);
    };
    const int gpuCounts = cudaDeviceCount() >= 2 ? 2 : 1;
    if (gpuCounts == 1) std::printf("one CUDA device: the two-GPU case skipped\n");
    for (Precision p : {Precision::Fp32, Precision::Fp64}) {
        // All pairs, and lists on several GPUs (whose rounds take all pairs on the gathered state); below
        // and above 2048 particles, where the full force pass stops being the one that takes a block a row
        // (force_kernels.cu: kRowBlockMaxRows) and the rounds' rows alone are.
        const std::pair<ForceModel, int64_t> cases[] = {{ForceModel::AllPairs, 1234},
                                                        {ForceModel::AllPairs, 4099},
                                                        {ForceModel::NeighbourList, 1234},
                                                        {ForceModel::NeighbourList, 4099}};
        for (const auto& [forces, count] : cases) {
            const Scene scene = ljWithCores(p, forces, count);
            for (int gpus = forces == ForceModel::AllPairs ? 1 : 2; gpus <= gpuCounts; ++gpus) {
                const auto fused = run(scene, gpus, true), separate = run(scene, gpus, false);
                const std::string where = std::string(precisionName(p)) + ", " + forceModelName(forces) + ", N = " +
                                          std::to_string(count) + ", " + std::to_string(gpus) + " GPU(s)";
                EXPECT_EQ(std::get<0>(fused), std::get<0>(separate)) << where << ": the state";
                EXPECT_EQ(std::get<1>(fused), std::get<1>(separate)) << where << ": the pair impacts";
                EXPECT_EQ(std::get<2>(fused), std::get<2>(separate)) << where << ": the wall impacts";
                EXPECT_EQ(std::get<3>(fused), std::get<3>(separate)) << where << ": the impact rounds";
                EXPECT_EQ(std::get<4>(fused), std::get<4>(separate)) << where << ": the dissipated energy";
                EXPECT_EQ(std::get<5>(fused), std::get<5>(separate)) << where << ": the kinetic energy";
                EXPECT_EQ(std::get<6>(fused), std::get<6>(separate)) << where << ": the contacts listed";
                EXPECT_EQ(std::get<7>(fused), std::get<7>(separate)) << where << ": the pair virial";
                // What the test is about: impacts in most steps, some needing a second round, energy dissipated.
                EXPECT_GT(std::get<1>(fused), 200) << where;
                EXPECT_GT(std::get<3>(fused), 2 * 200) << where;
                EXPECT_GT(std::get<4>(fused), 0.0) << where;
                std::printf("%s: %lld pair and %lld wall impacts in %lld rounds over 200 steps\n", where.c_str(),
                            (long long)std::get<1>(fused), (long long)std::get<2>(fused), (long long)std::get<3>(fused));
            }
        }
    }
}

TEST(CudaContacts, TheStageWithoutHostWaitsGivesTheBitsOfTheHostDrivenOne) {
    COREBOX_REQUIRE_GPU();
    auto run = [](const Scene& scene, int gpus, bool gaussSeidel, bool fused) {
        CudaBackendOptions options;
        options.precision = scene.integrator.precision;
        options.gpus = gpus;
        options.fusedSteps = fused;
        options.gaussSeidelContacts = gaussSeidel;
        Simulation sim(scene, makeCudaBackend(options), makeInitialState(scene));
        int64_t sweeps = 0, listings = 0, pairs = 0, rounds = 0;
        for (int k = 0; k < 360; ++k) {
            const StepReport r = sim.step();
            sweeps += r.contactSweeps;
            listings += r.contactListings;
            pairs += r.pairCollisions;
            rounds += r.rounds;
        }
        const ObservablesRow row = sim.observe();
        return std::make_tuple(stateHash(sim.state()), sweeps, listings, pairs, row.dissipated, row.kinetic, rounds);
    };
    const int gpuCounts = cudaDeviceCount() >= 2 ? 2 : 1;
    if (gpuCounts == 1) std::printf("one CUDA device: the two-GPU case skipped\n");
    for (Precision p : {Precision::Fp32, Precision::Fp64}) {
        const Scene scene = deepPile(p);
        for (int gpus = 1; gpus <= gpuCounts; ++gpus) {
          for (bool gaussSeidel : {true, false}) {
            const auto fused = run(scene, gpus, gaussSeidel, true), separate = run(scene, gpus, gaussSeidel, false);
            const std::string where = std::string(precisionName(p)) + ", " + std::to_string(gpus) + " GPU(s), " +
                                      (gaussSeidel ? "Gauss-Seidel" : "Jacobi");
            EXPECT_EQ(std::get<0>(fused), std::get<0>(separate)) << where << ": the state";
            EXPECT_EQ(std::get<1>(fused), std::get<1>(separate)) << where << ": the sweeps";
            EXPECT_EQ(std::get<2>(fused), std::get<2>(separate)) << where << ": the listings";
            EXPECT_EQ(std::get<3>(fused), std::get<3>(separate)) << where << ": the impacts";
            EXPECT_EQ(std::get<4>(fused), std::get<4>(separate)) << where << ": the dissipated energy";
            EXPECT_EQ(std::get<5>(fused), std::get<5>(separate)) << where << ": the kinetic energy";
            EXPECT_EQ(std::get<6>(fused), std::get<6>(separate)) << where << ": the impact rounds";
            EXPECT_GT(std::get<6>(fused), 2 * 360) << where << ": rounds beyond the first of a step";
            // The pile formed and its contacts were relaxed by many sweeps, most listings past the first
            // batch (the first sweep, then 8): what the test is about.
            EXPECT_GT(std::get<1>(fused), 9 * std::get<2>(fused)) << where;
            std::printf("%s: %lld sweeps in %lld listings, %lld impact rounds over 360 steps\n", where.c_str(),
                        (long long)std::get<1>(fused), (long long)std::get<2>(fused), (long long)std::get<6>(fused));
          }
        }
    }
}

// A listing of more than 32768 rows starts its colouring from colours spread by the rows' hashes
// (contact_gauss_seidel.cu), and a colour no row took leaves a gap in the bounds. 16,000 balls settling on
// a 40 x 40 floor list some 40,000 rows by 2 s (the CPU's listing of the scene: 38,000 at 1.5 s, rising):
// the coloured sweeps in one launch and a launch a colour must give
// the same bits (two contacts of a colour sharing a particle would race and part them), and the pile's
// conserved sum must not grow. The one launch also with 2 blocks (CudaBackendOptions::sweepBlocks), so
// that its threads take a colour's rows two at a time, as they do at 10^6 balls; fp32 and fp64.
TEST(CudaContacts, AListingColouredFromSpreadColoursGivesTheSameBitsInOneLaunchAndALaunchAColour) {
    COREBOX_REQUIRE_GPU();
    for (Precision p : {Precision::Fp32, Precision::Fp64}) {
        Scene scene = deepPile(p);
        scene.box.size = {40.0, 40.0, 12.0};
        scene.species[0].count = 16000;
        auto run = [&](bool fused, int sweepBlocks) {
            CudaBackendOptions options;
            options.precision = scene.integrator.precision;
            options.fusedSteps = fused;
            options.sweepBlocks = sweepBlocks;
            Simulation sim(scene, makeCudaBackend(options), makeInitialState(scene));
            const double start = sim.observe().conserved();
            int64_t most = 0;
            for (int k = 0; k < 480; ++k) most = std::max(most, sim.step().contacts);
            const ObservablesRow row = sim.observe();
            return std::make_tuple(stateHash(sim.state()), most, row.dissipated, row.conserved() - start, start);
        };
        const auto separate = run(false, 0);
        const std::string name = precisionName(p);
        for (int blocks : {0, 2}) {
            const auto fused = run(true, blocks);
            const std::string where = name + (blocks > 0 ? ", 2 blocks" : ", as many blocks as fit");
            EXPECT_GT(std::get<1>(fused), 32768) << where << ": the listing is large enough to spread its colours";
            EXPECT_EQ(std::get<0>(fused), std::get<0>(separate)) << where << ": the state";
            EXPECT_EQ(std::get<2>(fused), std::get<2>(separate)) << where << ": the dissipated energy";
            // The conserved sum not above its start by more than 1e-5 of it (fp32 positions).
            EXPECT_LT(std::get<3>(fused), 1e-5 * std::get<4>(fused)) << where << ": energy gained";
            std::printf("16000 balls, %s: at most %lld rows listed, conserved sum changed by %.3e of %.6g\n",
                        where.c_str(), (long long)std::get<1>(fused), std::get<3>(fused) / std::get<4>(fused),
                        std::get<4>(fused));
        }
    }
}

TEST(CudaContacts, SkippedCellBuildsGiveTheBitsOfBuiltOnes) {
    // A round of the batched impact rounds after the first skips its cell-list build where the rounds
    // since moved no particle out of its cell (cuda_collisions.cpp: runImpactRounds), leaving the arrays
    // that build would make: against every round building, the same state, impacts, rounds and
    // dissipation, in fp32 and fp64. 6,000 balls: above the one-launch builds, which keep no keys.
    COREBOX_REQUIRE_GPU();
    auto run = [](const Scene& scene, bool skip) {
        CudaBackendOptions options;
        options.precision = scene.integrator.precision;
        options.skipUnmovedCellBuilds = skip;
        return runImpacts(scene, options, 480, false);
    };
    for (Precision p : {Precision::Fp32, Precision::Fp64}) {
        Scene scene = deepPile(p);
        scene.box.size = {16.0, 16.0, 60.0};
        scene.species[0].count = 6000;
        const ImpactOutcome built = run(scene, false), skipped = run(scene, true);
        const std::string where = precisionName(p);
        expectSameImpacts(skipped, built, where);
        EXPECT_GT(built.rounds, 2 * 480) << where << ": rounds beyond the first of a step";
        EXPECT_GT(built.pairs, 6000) << where << ": the balls met";
    }
}

TEST(CudaContacts, CandidateRowsGiveTheBitsOfCellWalks) {
    // The batched impact rounds of more than 32,768 particles read candidate rows made when some
    // particle has moved most of half their margin since the last (gpu_launch.h CandidateRows) instead
    // of walking cells built again each round: against cells, the same state, impacts, rounds,
    // dissipation and log, in fp32 and fp64, with rows of 32 slots and of 4 (most rows then overflow
    // and are walked in the cells of the rows' build), and with a few heavier balls of radius 0.65 kept
    // out of the cells (cell_list.h: large particles, walked apart).
    COREBOX_REQUIRE_GPU();
    auto run = [](const Scene& scene, bool candidates, int slots, bool log) {
        CudaBackendOptions options;
        options.precision = scene.integrator.precision;
        options.impactCandidates = candidates;
        options.candidateSlots = slots;
        return runImpacts(scene, options, 240, log);
    };
    for (Precision p : {Precision::Fp32, Precision::Fp64}) {
        Scene scene = deepPile(p);
        scene.box.size = {40.0, 40.0, 60.0};
        scene.species[0].count = 40000;
        SpeciesDef heavy = scene.species[0];
        heavy.name = "heavy";
        heavy.count = 24;
        heavy.radius = 0.65;
        heavy.mass = 2.2;
        scene.species.push_back(heavy);
        ASSERT_TRUE(gpu::searchWalksAlone(40024)) << "rows are read where a search walks a thread a particle";
        ASSERT_GT(gpu::cellListIfMovedBlocks<float>(), 0) << "rows are made where the cells' build gates itself";
        for (bool log : {false, true}) {
            if (log && p == Precision::Fp64) continue;  // the log's path is the same code in both
            const ImpactOutcome cells = run(scene, false, 0, log);
            for (int slots : {0, 4}) {
                const ImpactOutcome rows = run(scene, true, slots, log);
                const std::string where = std::string(precisionName(p)) + (slots ? ", rows of 4" : ", rows of 32") +
                                          (log ? ", contact log on" : "");
                expectSameImpacts(rows, cells, where);
                expectSameLog(rows, cells, where);
            }
            EXPECT_GT(cells.rounds, 2 * 240) << "rounds beyond the first of a step";
            EXPECT_GT(cells.pairs, 40000) << "the balls met";
            std::printf("%s%s: %lld impacts in %lld rounds\n", precisionName(p), log ? ", contact log on" : "",
                        (long long)(cells.pairs + cells.walls), (long long)cells.rounds);
        }
    }
}

TEST(CudaContacts, SearchesNarrowedToTheActiveParticlesGiveTheBitsOfFullOnes) {
    // After a stage's first search, only the particles in the cells around the last round's active
    // ones search (cuda_collisions.cpp: narrowSearch), from 524,288 particles by default: here from any
    // count, against never, with the rounds queued in batches and one at a time, and with the contact
    // log on (its batches bounded by the log's room): the same state, impacts, rounds, dissipation and
    // log, in fp32 and fp64.
    COREBOX_REQUIRE_GPU();
    auto run = [](const Scene& scene, bool narrowed, bool fused, bool log) {
        CudaBackendOptions options;
        options.precision = scene.integrator.precision;
        options.fusedSteps = fused;
        options.narrowedSearchFrom = narrowed ? 0 : INT64_MAX;
        return runImpacts(scene, options, 360, log);
    };
    for (Precision p : {Precision::Fp32, Precision::Fp64}) {
        const Scene scene = deepPile(p);
        for (bool fused : {true, false}) {
            for (bool log : {false, true}) {
                const ImpactOutcome full = run(scene, false, fused, log), narrowed = run(scene, true, fused, log);
                const std::string where = std::string(precisionName(p)) + (fused ? ", rounds in batches" : ", a round a wait") +
                                          (log ? ", contact log on" : "");
                expectSameImpacts(narrowed, full, where);
                expectSameLog(narrowed, full, where);
                EXPECT_GT(full.rounds, 2 * 360) << where << ": rounds beyond the first of a step";
                if (log) {
                    EXPECT_EQ(full.records, full.pairs + full.walls) << where << ": a record an impact";
                }
            }
        }
    }
}

TEST(CudaContacts, FirstRoundsFromTheMoversGiveTheBitsOfEveryParticle) {
    // A stage's first impact round searches from the particles fast enough for an impact (collision_
    // resolution.h: startsActive), scattered in fp32 where later rounds are (cuda_collisions.cpp:
    // scattersSearch), against every particle searching: the same state, impacts, rounds, steps at the
    // round cap, dissipation and contact log, with the rounds queued in batches and one at a time.
    // 1. A floor of balls at rest, touching, and a few hundred balls thrown down onto it: the floor's
    //    balls start every stage inactive, and the impacts they take come from the movers' searches (in
    //    fp32 as offers).
    // 2. A pile dropped and landing, the dense case; and with the rounds capped, so that steps end at the
    //    cap and its final check runs.
    COREBOX_REQUIRE_GPU();
    auto options = [](Precision p, bool moversFirst, bool fused) {
        CudaBackendOptions o;
        o.precision = p;
        o.fusedSteps = fused;
        o.moversFirst = moversFirst;
        o.narrowedSearchFrom = 0;  // fp32: the first round scattered too
        return o;
    };
    for (Precision p : {Precision::Fp32, Precision::Fp64}) {
        const int side = p == Precision::Fp32 ? 200 : 90;  // fp32: enough balls for a thread a particle
        const int thrown = 400;
        Scene scene = deepPile(p);
        scene.box.size = {double(side), double(side), 12.0};
        scene.species[0].count = side * side + thrown;
        if (p == Precision::Fp32) {
            ASSERT_TRUE(gpu::searchWalksAlone(scene.species[0].count)) << "scattering needs a thread a particle";
        }
        ParticleState start;
        start.resize(size_t(scene.species[0].count));
        std::mt19937 random(5);
        std::uniform_real_distribution<double> across(1.0, side - 1.0), height(3.0, 11.0), sideways(-1.0, 1.0);
        for (int k = 0; k < side * side; ++k) start.position[size_t(k)] = {0.5 + k % side, 0.5 + k / side, 0.5};
        for (int k = side * side; k < scene.species[0].count; ++k) {
            start.position[size_t(k)] = {across(random), across(random), height(random)};
            start.velocity[size_t(k)] = {sideways(random), sideways(random), -4.0};
        }
        for (bool fused : {true, false}) {
            for (bool log : {false, true}) {
                const ImpactOutcome everyone = runImpactsFrom(scene, start, options(p, false, fused), 120, log);
                const ImpactOutcome movers = runImpactsFrom(scene, start, options(p, true, fused), 120, log);
                const std::string where = std::string(precisionName(p)) + ", a floor" +
                                          (fused ? ", rounds in batches" : ", a round a wait") +
                                          (log ? ", contact log on" : "");
                expectSameImpacts(movers, everyone, where);
                expectSameLog(movers, everyone, where);
                EXPECT_GT(everyone.pairs, thrown) << where << ": the thrown balls met the floor's";
                EXPECT_GT(everyone.slowAtEnd, side * side * 9 / 10)
                    << where << ": the floor's balls start their stages inactive";
                std::printf("%s: %lld impacts in %lld rounds, %lld of %lld balls slow at the end\n", where.c_str(),
                            (long long)(everyone.pairs + everyone.walls), (long long)everyone.rounds,
                            (long long)everyone.slowAtEnd, (long long)scene.species[0].count);
            }
        }
        Scene pile = deepPile(p);
        pile.box.size =
            p == Precision::Fp32 ? std::array<double, 3>{40.0, 40.0, 60.0} : std::array<double, 3>{20.0, 20.0, 60.0};
        pile.species[0].count = p == Precision::Fp32 ? 40000 : 8000;
        for (bool log : {false, true}) {
            const ImpactOutcome everyone = runImpacts(pile, options(p, false, true), 360, log);
            const ImpactOutcome movers = runImpacts(pile, options(p, true, true), 360, log);
            const std::string where = std::string(precisionName(p)) + ", a pile" + (log ? ", contact log on" : "");
            expectSameImpacts(movers, everyone, where);
            expectSameLog(movers, everyone, where);
            EXPECT_GT(everyone.pairs, pile.species[0].count) << where << ": the balls met";
        }
        // The same pile with the rounds capped at 3: steps end at the cap, whose final check searches from
        // every particle (in fp32 scattered, every particle active).
        pile.interaction.maxCollisionRounds = 3;
        for (bool fused : {true, false}) {
            const ImpactOutcome everyone = runImpacts(pile, options(p, false, fused), 240, false);
            const ImpactOutcome movers = runImpacts(pile, options(p, true, fused), 240, false);
            const std::string where =
                std::string(precisionName(p)) + ", a pile, 3 rounds a step" + (fused ? "" : ", a round a wait");
            expectSameImpacts(movers, everyone, where);
            EXPECT_GT(everyone.capHits, 10) << where << ": steps at the round cap";
            std::printf("%s: %lld steps of 240 at the cap\n", where.c_str(), (long long)everyone.capHits);
        }
    }
}

TEST(CudaContacts, ScatteredSearchesGiveTheBitsOfSearchesByEveryParticle) {
    // In fp32, a round after a stage's first that would be narrowed is searched by the last round's
    // active particles alone, which offer their inactive neighbours the pairs' events (cuda_collisions.cpp:
    // searchRound), where the search walks a thread a particle (more than 32,768 particles); here from
    // any count. A round whose last round left few active particles is scattered from their list, a warp
    // a particle (CudaBackendOptions::listedScatterMax), and where every particle searches the rounds (not
    // narrowed), such rounds are scattered that way too. Each against every particle searching, with the
    // rounds queued in batches and one at a time, and with the contact log on: the same state, impacts,
    // rounds, dissipation and log. (fp64 keeps the narrowed search:
    // SearchesNarrowedToTheActiveParticlesGiveTheBitsOfFullOnes.)
    COREBOX_REQUIRE_GPU();
    enum class Search { Everyone, Scattered, ScatteredUnlisted, SparseListed };
    auto run = [](const Scene& scene, Search search, bool fused, bool log) {
        CudaBackendOptions options;
        options.precision = scene.integrator.precision;
        options.fusedSteps = fused;
        options.scatteredSearch = search != Search::Everyone;
        options.narrowedSearchFrom = search == Search::Scattered || search == Search::ScatteredUnlisted ? 0 : INT64_MAX;
        options.listedScatterMax = search == Search::ScatteredUnlisted ? 0 : -1;
        return runImpacts(scene, options, 240, log);
    };
    Scene scene = deepPile(Precision::Fp32);
    scene.box.size = {40.0, 40.0, 60.0};
    scene.species[0].count = 40000;
    ASSERT_TRUE(gpu::searchWalksAlone(scene.species[0].count)) << "the scattered search needs a thread a particle";
    const std::pair<Search, const char*> searches[] = {{Search::Scattered, "scattered"},
                                                       {Search::ScatteredUnlisted, "scattered a thread a particle"},
                                                       {Search::SparseListed, "every particle, sparse rounds listed"}};
    for (bool fused : {true, false}) {
        for (bool log : {false, true}) {
            const ImpactOutcome everyone = run(scene, Search::Everyone, fused, log);
            for (const auto& [search, name] : searches) {
                const ImpactOutcome other = run(scene, search, fused, log);
                const std::string where = std::string(name) + (fused ? ", rounds in batches" : ", a round a wait") +
                                          (log ? ", contact log on" : "");
                expectSameImpacts(other, everyone, where);
                expectSameLog(other, everyone, where);
            }
            EXPECT_GT(everyone.rounds, 2 * 240) << "rounds beyond the first of a step";
            EXPECT_GT(everyone.pairs, 40000) << "the balls met";
            std::printf("%s%s: %lld impacts in %lld rounds\n", fused ? "rounds in batches" : "a round a wait",
                        log ? ", contact log on" : "", (long long)(everyone.pairs + everyone.walls),
                        (long long)everyone.rounds);
        }
    }
}
