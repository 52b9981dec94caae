// A small scene with collisions, walls, gravity, a thermostat and every observable, run on the GPU:
// the workload compute-sanitizer's memcheck and racecheck inspect (ctest gpu_memcheck and
// gpu_racecheck run this test under them).
#include "gpu_fixture.h"
#include "initial_conditions.h"
#include "simulation.h"

using namespace corebox;

TEST(CudaSanitized, SmallSceneWithCollisions) {
    COREBOX_REQUIRE_GPU();
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
    for (Precision p : {Precision::Fp64, Precision::Fp32}) {
        scene.integrator.precision = p;
        Simulation sim(scene, makeCudaBackend(CudaBackendOptions{p, 0}), makeInitialState(scene));
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
