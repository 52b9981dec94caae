// The pairs-once all-pairs pass (kernels/pairs_once_kernels.cu: each pair evaluated once, Newton's
// third law) against the ordered-pair pass that the conformance tests hold to the CPU oracle: the same
// accelerations within stated tolerances in both precisions, one species and several with a cutoff,
// N not a multiple of the tile; the same bits run to run; half the pair evaluations; on two GPUs
// sharing the pass, the same within the same tolerances and the same bits for every exchange method.
// Sizes are large enough that the pass applies (its tile pairs must fill every GPU). Skips, visibly,
// without a CUDA device (or without two, for the shared pass).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>

#include "gpu_fixture.h"
#include "device_model.h"
#include "initial_conditions.h"
#include "peer_exchange.h"
#include "simulation.h"
#include "state_hash.h"

using namespace corebox;

namespace {

// One LJ species without a cutoff (the report's model), or two with mixing and a cutoff run as all
// pairs, at number density 0.5 from a lattice; at rest, so that a kick of 1 leaves V = A.
Scene fluid(int64_t n, bool twoSpecies, Precision precision) {
    Scene scene;
    SpeciesDef a;
    a.name = "A";
    a.count = n;
    a.radius = 0.1;
    scene.species = {a};
    if (twoSpecies) {
        SpeciesDef b = a;
        b.name = "B";
        b.count = n / 3;
        b.mass = 2.0;
        b.sigma = 1.2;
        b.epsilon = 0.8;
        scene.species[0].count = n - b.count;
        scene.species.push_back(b);
        scene.interaction.mixing = {{1.0, 0.5}, {0.5, 0.9}};
        scene.interaction.cutoff = 3.0;
        scene.interaction.forces = ForceModel::AllPairs;
    }
    const double side = std::cbrt(double(n) / 0.5);
    scene.box.size = {side * 1.2, side, side / 1.2};
    scene.integrator.precision = precision;
    scene.thermostat.kind = ThermostatKind::None;
    scene.init.temperature = 0.0;
    scene.init.seed = 5;
    return scene;
}

struct Pass {
    ParticleState accelerations;  // velocity = A after one kick of 1 from rest
    ForceCounters counters;
};

Pass forcePass(const Scene& scene, bool pairsOnce, int gpus = 1, Exchange exchange = Exchange::Auto) {
    CudaBackendOptions options;
    options.precision = scene.integrator.precision;
    options.gpus = gpus;
    options.exchange = exchange;
    options.pairsOnce = pairsOnce;
    std::unique_ptr<Backend> backend = makeCudaBackend(options);
    DeviceModel model = deviceModelOf(stepParametersOf(scene));
    model.forces = ForceModel::AllPairs;
    backend->setModel(model);
    ParticleState state = makeInitialState(scene);
    for (auto& v : state.velocity) v = Vec3<double>{0, 0, 0};
    backend->setState(state);
    backend->computeAccelerations();
    backend->kick(1.0);
    return Pass{backend->state(), backend->forceCounters()};
}

// Largest |a_once - a_ordered| over the particles, relative to the largest |a|.
double largestDifference(const ParticleState& once, const ParticleState& ordered) {
    double difference = 0, scale = 0;
    for (size_t i = 0; i < once.size(); ++i) {
        difference = std::max(difference, std::sqrt(norm2(once.velocity[i] - ordered.velocity[i])));
        scale = std::max(scale, std::sqrt(norm2(ordered.velocity[i])));
    }
    return difference / scale;
}

struct Case {
    int64_t n;
    bool twoSpecies;
    Precision precision;
    double tolerance;  // relative to the largest acceleration
};

}  // namespace

TEST(CudaPairsOnce, MatchesTheOrderedPassAndEvaluatesEachPairOnce) {
    COREBOX_REQUIRE_GPU();
    // fp64: the two passes differ only in summation order; fp32 in its rounding over ~4e4 terms.
    for (const Case& c :
         {Case{40000 + 37, false, Precision::Fp64, 1e-12}, Case{40000 + 37, false, Precision::Fp32, 1e-5},
          Case{33333, true, Precision::Fp64, 1e-12}, Case{33333, true, Precision::Fp32, 1e-5}}) {
        const Scene scene = fluid(c.n, c.twoSpecies, c.precision);
        const Pass once = forcePass(scene, true), ordered = forcePass(scene, false);
        const std::string what = std::to_string(c.n) + (c.twoSpecies ? " two species, cutoff " : " one species ") +
                                 precisionName(c.precision);
        EXPECT_LT(largestDifference(once.accelerations, ordered.accelerations), c.tolerance) << what;
        const int64_t n = c.n;
        EXPECT_EQ(ordered.counters.allPairsEvaluations, n * (n - 1)) << what;
        // Each pair once, plus the diagonal tiles' every ordered pair: just over half.
        EXPECT_LT(once.counters.allPairsEvaluations, n * (n - 1) * 53 / 100) << what;
        EXPECT_GT(once.counters.allPairsEvaluations, n * (n - 1) / 2) << what;
    }
}

TEST(CudaPairsOnce, GivesTheSameBitsRunToRun) {
    COREBOX_REQUIRE_GPU();
    for (Precision p : {Precision::Fp32, Precision::Fp64}) {
        const Scene scene = fluid(40000 + 37, true, p);
        EXPECT_EQ(stateHash(forcePass(scene, true).accelerations), stateHash(forcePass(scene, true).accelerations))
            << precisionName(p);
    }
}

// Two GPUs share one pass: each an equal run of the tile pairs, the rows' sums added across GPUs in
// GPU order. Same accelerations as the ordered pass within the tolerances above, each pair evaluated
// once over both GPUs, and the same bits for every copy exchange as for DA, which reads the positions
// in place (they deliver the same positions), and run to run. NCCL apart (below): compute-sanitizer's
// memcheck runs it without API error reports (tests/gpu/sanitize.sh).
namespace {

const Case kSharedCases[] = {Case{40000 + 37, false, Precision::Fp64, 1e-12},
                             Case{40000 + 37, false, Precision::Fp32, 1e-5}, Case{33333, true, Precision::Fp64, 1e-12},
                             Case{33333, true, Precision::Fp32, 1e-5}};

std::string describe(const Case& c) {
    return std::to_string(c.n) + (c.twoSpecies ? " two species, cutoff " : " one species ") +
           precisionName(c.precision);
}

bool peerAccessBetweenTheFirstTwo() { return peerAccessProblem({0, 1}).empty(); }

}  // namespace

TEST(CudaPairsOnce, TwoGpusShareThePassAndGiveTheSameBitsForEveryCopyExchange) {
    COREBOX_REQUIRE_GPUS(2);
    if (!peerAccessBetweenTheFirstTwo())
        GTEST_SKIP() << "GPUs 0 and 1 have no peer access: the shared pass does not apply";
    for (const Case& c : kSharedCases) {
        const Scene scene = fluid(c.n, c.twoSpecies, c.precision);
        const Pass ordered = forcePass(scene, false);
        const Pass shared = forcePass(scene, true, 2, Exchange::Da);
        EXPECT_LT(largestDifference(shared.accelerations, ordered.accelerations), c.tolerance) << describe(c);
        const int64_t n = c.n;
        EXPECT_LT(shared.counters.allPairsEvaluations, n * (n - 1) * 53 / 100) << describe(c);
        EXPECT_GT(shared.counters.allPairsEvaluations, n * (n - 1) / 2) << describe(c);
        const uint64_t bits = stateHash(shared.accelerations);
        for (Exchange e : {Exchange::Dts, Exchange::Dta, Exchange::Da})
            EXPECT_EQ(stateHash(forcePass(scene, true, 2, e).accelerations), bits)
                << describe(c) << ", exchange " << exchangeName(e);
    }
}

TEST(CudaPairsOnce, TwoGpusShareThePassWithTheSameBitsOverNccl) {
    COREBOX_REQUIRE_GPUS(2);
    if (!peerAccessBetweenTheFirstTwo())
        GTEST_SKIP() << "GPUs 0 and 1 have no peer access: the shared pass does not apply";
    for (const Case& c : kSharedCases) {
        const Scene scene = fluid(c.n, c.twoSpecies, c.precision);
        EXPECT_EQ(stateHash(forcePass(scene, true, 2, Exchange::Nccl).accelerations),
                  stateHash(forcePass(scene, true, 2, Exchange::Da).accelerations))
            << describe(c);
    }
}

// Pass after pass: a GPU's next pass writes the row sums its peer read in the last one, ordered by the
// next exchange (PeerExchange::readsDone). Three RK4 steps (twelve passes) on two GPUs give the same
// bits with every exchange, and stay within rounding of one GPU.
TEST(CudaPairsOnce, TwoGpusOverManyPassesGiveTheSameBitsWithDtsDtaDaAndNccl) {
    COREBOX_REQUIRE_GPUS(2);
    if (!peerAccessBetweenTheFirstTwo())
        GTEST_SKIP() << "GPUs 0 and 1 have no peer access: the shared pass does not apply";
    Scene scene = fluid(40000 + 37, false, Precision::Fp64);
    scene.integrator.method = Method::Rk4;
    scene.integrator.dt = 1e-3;
    scene.init.temperature = 1.0;
    auto run = [&](int gpus, Exchange exchange) {
        CudaBackendOptions options;
        options.precision = Precision::Fp64;
        options.gpus = gpus;
        options.exchange = exchange;
        Simulation sim(scene, makeCudaBackend(options), makeInitialState(scene));
        for (int s = 0; s < 3; ++s) sim.step();
        return sim.state();
    };
    const ParticleState one = run(1, Exchange::Auto), shared = run(2, Exchange::Nccl);
    double worst = 0;
    for (size_t i = 0; i < one.size(); ++i)
        worst = std::max(worst, std::sqrt(norm2(one.position[i] - shared.position[i])));
    EXPECT_LT(worst, 1e-9 * scene.box.size[0]);
    for (Exchange e : {Exchange::Dts, Exchange::Dta, Exchange::Da})
        EXPECT_EQ(stateHash(run(2, e)), stateHash(shared)) << "exchange " << exchangeName(e) << " against nccl";
}
