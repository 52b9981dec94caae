// The elastic hard-sphere fluid against theory (issue 9, item 4), on every backend: restitution 1, no
// pair force, no gravity, no thermostat, a simple cubic lattice start at packing fraction phi over
// the box (bench_scenes.h: hardSphereFluidScene), equilibrated, then measured:
// - energy: no potential, so the kinetic energy is the energy; the conserved sum is exact over the
//   measurement, and the kinetic energy itself is kept to rounding (1e-10 of itself, fp64): the
//   rare overlaps the impact rounds cannot take (an earlier impact of the step turned one of the
//   pair) bounce elastically in the contact phase (contact_relaxation.h: ContactBounce). Before they
//   did, they were stopped and took 2.8e-5 at phi = 0.35 with N = 8000 over 8 tau;
// - pressure: the whole walls and the whole-box virial (pressure.h) agree within 1% (one identity in
//   the time average); the walls' centres, where the momentum is the bulk's pressure, give
//   Z = P / (n_b kT_b) within 3% of Carnahan-Starling at the bulk packing fraction, and so does the
//   bulk's own virial pressure from the velocity changes in the central region;
// - collisions: the collision frequency per particle in the central region within 5% of Enskog's
//   with the Carnahan-Starling contact value at the bulk density and temperature.
// The bulk (hard_sphere_measures.h) is a cube 3 (phi = 0.35) or 5 (0.45) diameters inside the region
// open to centres: the layering next to the walls has died out there (the density does not change
// when the margin grows), and its density, not N / V, is what Z and Enskog need. Its temperature is
// measured too and used: a region of a few thousand particles keeps the random temperature it got
// at the last velocity draw (standard deviation sqrt(2 / (3 N_region)), 1-3% here) for as long as
// heat takes to conduct out of it, longer than the run.
//
// Tolerances against statistics: at phi = 0.35, N = 2000, 12 tau measured, the wall centres receive
// ~6,000 hits and the bulk ~50,000 collisions: about 1% on Z and on the rate (this run, CPU: Z at the
// wall centres -1.7%, bulk virial -1.1%, rate -0.7%). The runs are deterministic for a backend (fixed
// seed, fixed summation order), so a pass is reproducible on one build.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>

#include "bench_scenes.h"
#include "hard_sphere_measures.h"
#include "hard_sphere_theory.h"
#include "physics_fixtures.h"
#include "pressure.h"

using namespace corebox;
using namespace corebox::testing;

namespace {

class HardSphereFluid : public OnEveryBackend {};

struct FluidResult {
    double kineticChange = 0;    // relative, over the measurement
    double conservedChange = 0;  // relative, over the measurement
    double phiBulk = 0, zCs = 0;
    double zWallCentre = 0, zBulkVirial = 0;
    double pressureWall = 0, pressureVirial = 0;
    double rate = 0, enskog = 0;
};

// Collisions per particle per step: 0.02 at Enskog's rate for the box's packing fraction.
constexpr double kCollisionsPerStep = 0.02;
// margin: the bulk cube's faces, in diameters inside the region open to centres.
FluidResult runFluid(const std::string& backend, int64_t n, double phi, double equilibrate, double measure, double margin) {
    const double dt = kCollisionsPerStep / enskogCollisionFrequency(6 * phi / M_PI, 1.0, 1.0, 1.0);
    const Scene scene = hardSphereFluidScene(n, phi, Precision::Fp64, dt);
    // Equilibrated in 8 stretches with velocities redrawn before each (hard_sphere_measures.h: the
    // density settles isothermally), then measured without.
    auto sim = equilibrateIsothermally(scene, makeInitialState(scene), equilibrate, 8,
                                       [&](const Scene& sc, const ParticleState& st) { return makeSimulation(backend, sc, st); });
    const ObservablesRow start = sim->observe();  // opens the pressure window
    BulkSampler bulk{bulkRegionOf(scene.box.size, 0.5, margin)};
    ParticleState before = sim->state();
    const int64_t steps = std::llround(measure / dt);
    for (int64_t s = 0; s < steps; ++s) {
        const StepReport report = sim->step();
        ParticleState after = sim->state();
        bulk.sampleStep(before, after, report.dt);
        if (s % 10 == 0) bulk.sampleDensity(after);
        before = std::move(after);
    }
    const ObservablesRow end = sim->observe();
    FluidResult r;
    r.kineticChange = (end.kinetic - start.kinetic) / start.kinetic;
    r.conservedChange = (end.conserved() - start.conserved()) / start.conserved();
    const double nb = bulk.density(), kT = bulk.temperature();
    r.phiBulk = packingFractionOf(nb, 1.0);
    r.zCs = carnahanStarlingZ(r.phiBulk);
    r.zWallCentre = end.pressureWallCentre / (nb * kT);
    r.zBulkVirial = bulk.virialPressure() / (nb * kT);
    r.pressureWall = end.pressureWall;
    r.pressureVirial = end.pressureVirial;
    r.rate = bulk.collisionFrequency();
    r.enskog = enskogCollisionFrequency(nb, 1.0, kT, 1.0);
    return r;
}

void expectTheory(const FluidResult& r) {
    ::testing::Test::RecordProperty("phi_bulk", std::to_string(r.phiBulk));
    ::testing::Test::RecordProperty("z_cs", std::to_string(r.zCs));
    ::testing::Test::RecordProperty("z_wall_centre", std::to_string(r.zWallCentre));
    ::testing::Test::RecordProperty("z_bulk_virial", std::to_string(r.zBulkVirial));
    ::testing::Test::RecordProperty("rate_over_enskog", std::to_string(r.rate / r.enskog));
    ::testing::Test::RecordProperty("kinetic_change", std::to_string(r.kineticChange));
    EXPECT_LT(std::fabs(r.conservedChange), 1e-12);
    EXPECT_LT(std::fabs(r.kineticChange), 1e-10);
    EXPECT_NEAR(r.pressureWall / r.pressureVirial, 1.0, 0.01) << "the two whole-box routes are one identity";
    EXPECT_NEAR(r.zWallCentre / r.zCs, 1.0, 0.03) << "Z at the walls' centres " << r.zWallCentre << ", Carnahan-Starling "
                                                  << r.zCs << " at phi_bulk " << r.phiBulk;
    EXPECT_NEAR(r.zBulkVirial / r.zCs, 1.0, 0.03) << "bulk virial Z " << r.zBulkVirial << ", Carnahan-Starling " << r.zCs;
    EXPECT_NEAR(r.rate / r.enskog, 1.0, 0.05) << "collision frequency " << r.rate << ", Enskog " << r.enskog;
}

}  // namespace

INSTANTIATE_TEST_SUITE_P(Backends, HardSphereFluid, ::testing::ValuesIn(backendNames()), backendInstanceName);

TEST_P(HardSphereFluid, AtPhi035MatchesCarnahanStarlingAndEnskog) {
    // 2,000 spheres (box 14.4, bulk phi ~0.378), dt = 1.4e-3: 2 tau of equilibration (~30 collisions
    // per particle, the lattice long molten), 12 tau measured (8,500 steps). ~30 s on 2 CPU cores.
    expectTheory(runFluid(backendName(), 2000, 0.35, 2.0, 12.0, 3.0));
}

TEST_P(HardSphereFluid, AtPhi045MatchesCarnahanStarlingAndEnskog) {
    // 32,000 spheres (box 33.4, bulk phi ~0.455, below freezing at 0.494), dt = 7e-4: 2 tau of
    // equilibration (~60 collisions per particle), 6 tau measured, ~11,400 steps. The walls' layering
    // reaches further at this density: the bulk cube is 5 diameters inside (at 3 it still held part
    // of the layers and Z came out 3-6% high; at 5, 6 and 8 the CPU measured Z within 1% and the rate
    // within 0.6%). ~15 minutes on a 2-core CPU: the cpu instance runs only when asked.
    if (backendName() == "cpu" && !std::getenv("COREBOX_SLOW_TESTS"))
        GTEST_SKIP() << "too slow for CI on the CPU (~15 min): runs on cuda; set COREBOX_SLOW_TESTS=1 to run it on the cpu";
    expectTheory(runFluid(backendName(), 32000, 0.45, 2.0, 6.0, 5.0));
}
