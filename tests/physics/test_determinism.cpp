// Same scene, same seed: bit-identical states, whatever the thread count. Covers placement,
// velocities, forces, collisions and the thermostat's draws.
#include <gtest/gtest.h>

#include "physics_fixtures.h"
#include "state_hash.h"

using namespace corebox;
using namespace corebox::testing;

namespace {

uint64_t runHash(int threads, uint64_t seed, Placement placement) {
    Scene scene;
    SpeciesDef a, b;
    a.name = "A";
    a.count = 300;  // above the serial threshold, so two threads really split the loops
    a.radius = 0.45;
    b.name = "B";
    b.count = 200;
    b.mass = 2.0;
    b.radius = 0.5;
    scene.species = {a, b};
    scene.interaction.mixing = {{1.0, 0.4}, {0.4, 1.0}};
    scene.interaction.restitution = 0.9;
    scene.box.size = {11, 11, 11};
    scene.integrator.method = Method::Rk4;
    scene.integrator.dt = 2e-3;
    scene.thermostat.kind = ThermostatKind::Bussi;
    scene.init.seed = seed;
    scene.init.placement = placement;
    auto sim = makeSimulation(scene, threads);
    for (int s = 0; s < 150; ++s) sim->step();
    return stateHash(sim->state());
}

}  // namespace

TEST(Determinism, SameSeedSameHashOnOneAndTwoThreads) {
    const uint64_t one = runHash(1, 7, Placement::Random);
    EXPECT_EQ(one, runHash(2, 7, Placement::Random));
    EXPECT_EQ(one, runHash(1, 7, Placement::Random));
    EXPECT_NE(one, runHash(1, 8, Placement::Random));  // the seed matters
    EXPECT_EQ(runHash(1, 3, Placement::Lattice), runHash(2, 3, Placement::Lattice));
}
