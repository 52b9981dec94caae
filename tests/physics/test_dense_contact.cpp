// Dense contact (collision_rounds.h, kernels/contact_relaxation.h), on every backend:
// - a random configuration full of overlaps handed to the collision stage: kinetic plus potential
//   energy never rises, the overlaps are gone to the relaxation's tolerance, and momentum is exact
//   (away from the walls, which are the only external impulses);
// - an overlapping pair the impacts cannot take, alone in the contact list, bounces with its
//   restitution (an elastic fluid keeps its energy);
// - a ball resting on the floor and a column of ten balls stay put for 10^4 steps under gravity: no
//   creep sideways, no sinking, no overlap, and the energy they lose is what the conserved sum books;
// - a settled pile holds every layer: no layer keeps falling onto the one below, no round cap, small
//   overlaps;
// - a listing again within a step starts from the impulses the step gave so far, and the step keeps
//   them whole for the next one;
// - a stage's first impact round searched from the movers alone finds what every particle finds (CPU;
//   the GPU's in tests/gpu/test_cuda_contacts.cpp);
// - the pressure bookkeeping of both phases: a resting ball presses on the floor with its weight, and
//   in a pile the momentum given to the walls balances gravity and the pile's momentum change; a cold
//   column's first step books the pair virial of its weight, and a settled pile's pair virial closes the
//   virial theorem's balance with gravity and the walls.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "collision_rounds.h"
#include "cpu_backend.h"
#include "physics_fixtures.h"
#include "pressure.h"
#include "state_hash.h"

using namespace corebox;
using namespace corebox::testing;

namespace {

class DenseContact : public OnEveryBackend {};

// Largest overlap as a fraction of the contact distance (equal radii a), and penetration of walls.
double worstOverlap(const ParticleState& st, double radius, const std::array<double, 3>& box) {
    double worst = 0;
    for (size_t i = 0; i < st.size(); ++i) {
        for (size_t j = i + 1; j < st.size(); ++j) {
            worst = std::max(worst, 1.0 - std::sqrt(norm2(st.position[i] - st.position[j])) / (2 * radius));
        }
        for (int a = 0; a < 3; ++a) {
            worst = std::max(worst, (radius - st.position[i][a]) / (2 * radius));
            worst = std::max(worst, (st.position[i][a] - (box[size_t(a)] - radius)) / (2 * radius));
        }
    }
    return worst;
}

// 400 balls of radius 0.5 on a lattice in a 10 x 24 x 10 box, gravity -9.81 along y, restitution
// 0.5 with each other and the walls, dt = 1/240.
Scene pileOf400() {
    Scene scene = hardSphereScene(400, 10.0, Method::Verlet, 1.0 / 240);
    scene.box.size = {10.0, 24.0, 10.0};
    scene.interaction.gravity = {0, -9.81, 0};
    scene.interaction.restitution = 0.5;
    scene.box.wallRestitution = 0.5;
    scene.init.temperature = 0.1;
    return scene;
}

// `count` balls in a 12-wide box at dt = 1/240 under gravity -9.81 along y, restitution 0.5 with each
// other and the walls.
Scene columnScene(int count) {
    Scene scene = hardSphereScene(count, 12.0, Method::Verlet, 1.0 / 240);
    scene.interaction.gravity = {0, -9.81, 0};
    scene.interaction.restitution = 0.5;
    scene.box.wallRestitution = 0.5;
    return scene;
}

// A column of `count` balls of radius 0.5 at rest at x = z = 6, touching each other, the lowest centre
// at y = `bottom` (0.5: touching the floor).
ParticleState columnAt(int count, double bottom) {
    ParticleState st;
    st.resize(size_t(count));
    for (int i = 0; i < count; ++i) {
        st.position[size_t(i)] = {6.0, bottom + 1.0 * i, 6.0};
        st.velocity[size_t(i)] = {0, 0, 0};
        st.species[size_t(i)] = 0;
    }
    return st;
}

// 300 balls of radius 0.5 at random in the middle 8^3 of a 20^3 box (packing fraction 0.3 there: most
// overlap several neighbours), with random velocities.
ParticleState randomOverlaps(uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> where(6.0, 14.0), speed(-1.0, 1.0);
    ParticleState st;
    st.resize(300);
    for (size_t i = 0; i < st.size(); ++i) {
        st.position[i] = {where(rng), where(rng), where(rng)};
        st.velocity[i] = {speed(rng), speed(rng), speed(rng)};
        st.species[i] = 0;
    }
    return st;
}

Vec3<double> momentum(const ParticleState& st) {
    Vec3<double> p{0, 0, 0};
    for (const Vec3<double>& v : st.velocity) p += v;  // unit masses
    return p;
}

}  // namespace

INSTANTIATE_TEST_SUITE_P(Backends, DenseContact, ::testing::ValuesIn(backendNames()), backendInstanceName);

TEST_P(DenseContact, OverlapsHandedToTheStageAddNoEnergyAndKeepMomentum) {
    // 300 balls overlapping at random (randomOverlaps), no forces, no gravity. One step of 1e-6 moves
    // nothing by itself; the collision stage must sort the overlaps out.
    for (uint64_t seed = 1; seed <= 8; ++seed) {
        Scene scene = hardSphereScene(300, 20.0, Method::Verlet, 1e-6);
        scene.interaction.restitution = 0.5;
        const ParticleState st = randomOverlaps(seed);
        auto sim = makeSimulation(backendName(), scene, st);
        const ObservablesRow before = sim->observe();
        const double overlapBefore = worstOverlap(st, 0.5, scene.box.size);
        ASSERT_GT(overlapBefore, 0.3) << "the test needs deep overlaps";
        const StepReport report = sim->step();
        const ObservablesRow after = sim->observe();
        const ParticleState end = sim->state();
        // No external impulse: the particles stay far from the walls (a move of at most an overlap).
        const Vec3<double> dp = momentum(end) - momentum(st);
        EXPECT_LT(std::sqrt(norm2(dp)), 1e-12 * 300) << "seed " << seed;
        // E_kin + E_pot may only fall; the conserved sum books what fell (dissipated) exactly.
        EXPECT_LE(after.kinetic + after.potential, before.kinetic + before.potential + 1e-12) << "seed " << seed;
        EXPECT_NEAR(after.conserved(), before.conserved(), 1e-10) << "seed " << seed;
        EXPECT_GT(report.contacts, 0);
        // The relaxation's tolerance (1e-3 of a diameter) is met or the sweep cap says it was not.
        const double overlapAfter = worstOverlap(end, 0.5, scene.box.size);
        RecordProperty("overlap_after_seed_" + std::to_string(seed), std::to_string(overlapAfter));
        EXPECT_LT(overlapAfter, 0.01) << "seed " << seed << ", " << report.contactSweeps << " sweeps";
    }
}

TEST_P(DenseContact, AnIsolatedOverlapTheImpactsCannotTakeBouncesWithItsRestitution) {
    // Two balls overlapping by a fifth of a diameter, closing at 2: the straight-line rewind to
    // contact (0.1) is far beyond the step (1e-3), so it is no impact of this step, as when an earlier
    // impact of the step turned one of them. Alone in the contact list, the pair bounces with e: an
    // elastic fluid keeps its energy to rounding, and an inelastic one loses (1 - e^2) mu vn^2 / 2.
    for (double e : {1.0, 0.5}) {
        Scene scene = hardSphereScene(2, 20.0, Method::Verlet, 1e-3);
        scene.interaction.restitution = e;
        ParticleState st;
        st.resize(2);
        st.position[0] = {9.6, 10.0, 10.0};
        st.position[1] = {10.4, 10.0, 10.0};
        st.velocity[0] = {1.0, 0.25, 0.0};
        st.velocity[1] = {-1.0, 0.25, 0.0};  // a common tangential drift keeps the line of centres on x
        st.species[0] = st.species[1] = 0;
        auto sim = makeSimulation(backendName(), scene, st);
        const ObservablesRow before = sim->observe();
        const StepReport report = sim->step();
        const ObservablesRow after = sim->observe();
        const ParticleState end = sim->state();
        EXPECT_EQ(report.pairCollisions, 0) << "the test needs an overlap the impacts do not take";
        EXPECT_GT(report.contacts, 0);  // the pair (counted once or from both sides, by backend)
        const double vn = end.velocity[1].x - end.velocity[0].x;  // separation speed along x
        EXPECT_NEAR(vn, e * 2.0, 1e-12) << "e " << e;
        EXPECT_NEAR(end.velocity[0].y, 0.25, 1e-15);  // tangential motion untouched
        EXPECT_NEAR(end.velocity[1].y, 0.25, 1e-15);
        const double loss = 0.5 * (1 - e * e) * 0.5 * 2.0 * 2.0;  // mu = 1/2, vn = 2
        EXPECT_NEAR(before.kinetic - after.kinetic, loss, 1e-12) << "e " << e;
        EXPECT_NEAR(after.dissipated - before.dissipated, loss, 1e-12) << "e " << e;
        EXPECT_LT(std::sqrt(norm2(momentum(end) - momentum(st))), 1e-14);
        EXPECT_LT(worstOverlap(end, 0.5, scene.box.size), 2e-3);
    }
}

TEST_P(DenseContact, ABallOnTheFloorAndAColumnOfTenStayPut) {
    // Balls of radius 0.5 touching the floor (y = 0.5) and each other, gravity -9.81 along y,
    // restitution 0.5, dt = 1/240: 10^4 steps (42 s).
    for (int count : {1, 10}) {
        const Scene scene = columnScene(count);
        const ParticleState st = columnAt(count, 0.5);
        auto sim = makeSimulation(backendName(), scene, st);
        const double conserved0 = sim->observe().conserved();
        for (int s = 0; s < 10000; ++s) sim->step();
        const ParticleState end = sim->state();
        const ObservablesRow row = sim->observe();
        double drift = 0, sink = 0;
        for (int i = 0; i < count; ++i) {
            const Vec3<double> d = end.position[size_t(i)] - st.position[size_t(i)];
            drift = std::max(drift, std::sqrt(d.x * d.x + d.z * d.z));
            sink = std::max(sink, std::fabs(d.y));
        }
        RecordProperty("sink_" + std::to_string(count), std::to_string(sink));
        EXPECT_LT(drift, 1e-9) << count << " balls crept sideways";
        // Each step gravity moves the column by g dt^2 / 2 = 8.5e-5 before the stage lifts it back.
        EXPECT_LT(sink, 2e-4) << count << " balls sank or rose";
        EXPECT_LT(worstOverlap(end, 0.5, scene.box.size), 2e-4) << count;
        EXPECT_LT(row.kinetic, 1e-3 * count) << count << " balls are not at rest";
        EXPECT_NEAR(row.conserved(), conserved0, 1e-9 * std::fabs(conserved0)) << count;
    }
}

TEST_P(DenseContact, AListingAgainInAStepCarriesTheStepsImpulses) {
    // A column of ten balls at rest, the bottom one pressed 3% of a diameter into the floor: the first
    // sweep sees the deep overlap, so the step lists its contacts again after the first relaxation
    // (collision_rounds.cpp). The first relaxation already holds the column up; the second starts
    // from the impulses the first gave (contact_relaxation.h), so the step ends with the floor's whole
    // push, about the column's weight times dt, for the next step's warm start. Started from 0, the
    // second listing would keep only the little it added.
    const int count = 10;
    const Scene scene = columnScene(count);
    auto sim = makeSimulation(backendName(), scene, columnAt(count, 0.47));
    const StepReport report = sim->step();
    ASSERT_GE(report.contactListings, 2) << "the deep overlap did not list again: the test tests nothing";
    const int64_t floorCode = -1 - (2 * 1 + 0);  // axis y, side 0
    double floorPush = 0;
    for (const ContactWarmStart& w : sim->backend().contactWarmStart().impulses) {
        if (w.i == 0 && w.partner == floorCode) floorPush = w.lambda;  // per unit mass, m = 1
    }
    const double weightImpulse = count * 9.81 * scene.integrator.dt;
    EXPECT_GT(floorPush, 0.9 * weightImpulse) << "the floor's impulse kept for the next step";
    EXPECT_LT(floorPush, 2.0 * weightImpulse);
}

// ---- pressure bookkeeping of the contact phase (pressure.h, impulse_sums.h) ----

TEST_P(DenseContact, ABallOnTheFloorPressesWithItsWeight) {
    // The ball of the test above: it rests, so every step the contact phase gives the floor the
    // momentum gravity gave the ball, m g dt. Over a window of 480 steps the floor received m g t and
    // nothing else did: the wall pressure is m g over the area of the six walls (pressure.h), and m g
    // over a quarter of it at the walls' centres, where the ball sits.
    Scene scene = hardSphereScene(1, 12.0, Method::Verlet, 1.0 / 240);
    scene.interaction.gravity = {0, -9.81, 0};
    scene.interaction.restitution = 0.5;
    scene.box.wallRestitution = 0.5;
    auto sim = makeSimulation(backendName(), scene, stateOf({{6.0, 0.5, 6.0}}, {{0, 0, 0}}));
    for (int s = 0; s < 240; ++s) sim->step();
    sim->observe();  // opens the window
    for (int s = 0; s < 480; ++s) sim->step();
    const ObservablesRow row = sim->observe();
    const double weight = 9.81 * row.window;  // m g t, m = 1
    const int floor = 2 * 1 + 0;              // axis y, side 0
    EXPECT_NEAR(row.window, 2.0, 1e-12);
    EXPECT_NEAR(row.impulses.wall[floor], weight, 1e-9 * weight);
    EXPECT_NEAR(row.impulses.wallCentre[floor], weight, 1e-9 * weight);
    for (int w = 0; w < kWallCount; ++w) {
        if (w != floor) {
            EXPECT_EQ(row.impulses.wall[w], 0.0) << "wall " << w;
        }
    }
    EXPECT_EQ(row.impulses.pairVirial, 0.0);
    const PressureGeometry g = pressureGeometryOf(scene);  // faces of the 11^3 region open to centres
    EXPECT_NEAR(g.totalArea, 6 * 11.0 * 11.0, 1e-12);
    EXPECT_NEAR(row.pressureWall, 9.81 / g.totalArea, 1e-9 * 9.81 / g.totalArea);
    EXPECT_NEAR(row.pressureWallCentre, 9.81 / (0.25 * g.totalArea), 1e-9 * 9.81 / g.totalArea);
    // The virial route: no kinetic energy, no pairs; the floor's push is not a pair impulse.
    EXPECT_NEAR(row.pressureVirial, 0.0, 1e-12);
}

TEST_P(DenseContact, MomentumGivenToTheWallsBalancesGravityInAPile) {
    // 400 balls of radius 0.5 dropped from a lattice into a 10 x 24 x 10 box (gravity -9.81 along y,
    // restitution 0.5, dt = 1/240). Newton over any window, with the walls the only external impulses
    // besides gravity: p(t1) - p(t0) = M g (t1 - t0) + sum over walls of the momentum they gave (each
    // wall receives I_w along its outward normal and gives it back inward), to rounding. This holds
    // while the balls land (impacts) and once the pile rests (contacts carry the weight, layer by
    // layer, to the floor). Once the pile rests (4 s after the drop) p hardly changes: the floor bears the
// weight, M g t, within 1%.
    auto sim = makeSimulation(backendName(), pileOf400());
    const double mass = 400.0, g = 9.81;
    ObservablesRow start = sim->observe();
    const double potential0 = start.potential;
    for (const auto& [steps, settledWindow] : {std::pair<int, bool>{480, false}, {720, false}, {240, true}}) {
        for (int s = 0; s < steps; ++s) sim->step();
        const ObservablesRow end = sim->observe();
        const ImpulseSums& I = end.impulses;
        const double weight = mass * g * end.window;
        SCOPED_TRACE("window ending at t = " + std::to_string(end.time));
        // Outward normals: -x, +x, -y, +y, -z, +z for walls 0 .. 5.
        EXPECT_NEAR(end.px - start.px, I.wall[0] - I.wall[1], 1e-9 * weight);
        EXPECT_NEAR(end.py - start.py, -weight + I.wall[2] - I.wall[3], 1e-9 * weight);
        EXPECT_NEAR(end.pz - start.pz, I.wall[4] - I.wall[5], 1e-9 * weight);
        if (settledWindow) {
            // At rest as `corebox bench pile` judges it: kinetic energy a small fraction of what fell.
            EXPECT_LT(end.kinetic, 1e-3 * (potential0 - end.potential)) << "the pile is not at rest";
            EXPECT_NEAR(I.wall[2], weight, 0.01 * weight) << "the floor does not bear the pile's weight";
            EXPECT_GT(I.pairVirial, 0.0);  // contacts between balls carry it down
            RecordProperty("floor_over_weight", std::to_string(I.wall[2] / weight));
        }
        start = end;
    }
}

TEST_P(DenseContact, ASettledPileHoldsEveryLayer) {
    // The pile of the test above, 5 s after the drop, over one more second. Every touching contact
    // that is not approaching fast is listed (contact_relaxation.h), so the layers above the floor
    // are held with it: none keeps falling onto the layer below (the pile's mean vertical speed stays
    // a small part of what gravity adds in a step), no step needs the round cap, and the overlaps
    // left are a quarter of the 1e-3 of a contact distance that bounds any contact phase. (Listing
    // only the approaching contacts, the pile fell at 0.13 per ball on the CPU, 0.072 on an H200.)
    auto sim = makeSimulation(backendName(), pileOf400());
    for (int s = 0; s < 1200; ++s) sim->step();
    int64_t capHits = 0;
    double worstFall = 0, worstOverlap = 0;
    for (int s = 0; s < 240; ++s) {
        const StepReport r = sim->step();
        capHits += r.roundCapHit ? 1 : 0;
        worstOverlap = std::max(worstOverlap, r.contactOverlap);
        worstFall = std::max(worstFall, -sim->observe().py / 400.0);
    }
    RecordProperty("worst_mean_fall_speed", std::to_string(worstFall));
    RecordProperty("worst_overlap", std::to_string(worstOverlap));
    EXPECT_EQ(capHits, 0);
    EXPECT_LT(worstFall, 0.25 * 9.81 / 240) << "the pile is falling onto its lower layers";
    EXPECT_LT(worstOverlap, 2.5e-4);  // listing only approaching contacts left 2.3e-3 (CPU) and 5e-4 (H200)
}

TEST_P(DenseContact, AColdColumnsFirstStepBooksThePairVirialOfItsWeight) {
    // A column of ten balls at rest, touching each other and the floor, and no impulses from a step
    // before: the contact phase's first step is the whole of its pair impulses, none from a warm start.
    // It stops what gravity added in the step, so the contact between balls k and k + 1 (from the
    // bottom, one diameter apart) carries the (9 - k) balls above, (9 - k) m g dt, and the pair virial of
    // the step is sum_k 1.0 (9 - k) g dt = 45 g dt, the floor's impulse 10 g dt. Within 5%: the sweeps
    // stop at a speed tolerance of a tenth of g dt. The GPU takes the pair virial after its sweeps
    // (pairVirialsKernel); a virial taken from impulses already handed back, or not taken, books none.
    const int count = 10;
    const Scene scene = columnScene(count);
    auto sim = makeSimulation(backendName(), scene, columnAt(count, 0.5));
    const StepReport report = sim->step();
    const double gdt = 9.81 * scene.integrator.dt;
    ASSERT_GT(report.contacts, 0) << "nothing listed: the test tests nothing";
    RecordProperty("pair_virial_over_45_g_dt", std::to_string(report.impulses.pairVirial / (45 * gdt)));
    EXPECT_NEAR(report.impulses.pairVirial, 45 * gdt, 0.05 * 45 * gdt);
    EXPECT_NEAR(report.impulses.wall[2 * 1 + 0], count * gdt, 0.05 * count * gdt);  // the floor
}

TEST_P(DenseContact, ThePairVirialOfASettledPileBalancesGravityAndTheWalls) {
    // The virial theorem over a window: d/dt sum m x . v = 2 K + sum x . F, so over a window of length t
    //   Delta(sum m x . v) = 2 int K dt + W_pair + W_walls - M g int ybar dt,
    // with W_pair the pair virial (ImpulseSums::pairVirial: sum r_ij . J_ij) and W_walls = sum over axes
    // of a I_(wall at 0) - (L - a) I_(wall at L) (a wall's impulse acts on centres at a or L - a). The
    // pile of the tests above, settled (5 s), over one more second: K and Delta(sum m x . v) are a few
    // 1e-4 of the gravity term, so the pair virial the contact phase counts must close the balance to 1%.
    // Most of a settled pile's pair virial is booked by the warm start (the impulses of the step before,
    // applied before the sweeps); the sweeps' own part is checked by the cold column above.
    const Scene scene = pileOf400();
    auto sim = makeSimulation(backendName(), scene);
    for (int s = 0; s < 1200; ++s) sim->step();
    const double mass = 400.0, g = 9.81, a = 0.5;
    auto moments = [&](double* xv, double* ybar) {
        const ParticleState st = sim->state();
        *xv = 0;
        *ybar = 0;
        for (size_t i = 0; i < st.size(); ++i) {
            *xv += dot(st.position[i], st.velocity[i]);  // m = 1
            *ybar += st.position[i].y / double(st.size());
        }
    };
    double xv0 = 0, y0 = 0, xv1 = 0, y1 = 0;
    moments(&xv0, &y0);
    sim->observe();  // opens the window
    for (int s = 0; s < 240; ++s) sim->step();
    const ObservablesRow row = sim->observe();
    moments(&xv1, &y1);
    const ImpulseSums& I = row.impulses;
    double wallVirial = 0;
    for (int axis = 0; axis < 3; ++axis)
        wallVirial += a * I.wall[2 * axis] - (scene.box.size[axis] - a) * I.wall[2 * axis + 1];
    const double gravity = mass * g * 0.5 * (y0 + y1) * row.window;
    const double balance = I.pairVirial + wallVirial - gravity - (xv1 - xv0);
    RecordProperty("pair_virial_over_gravity_term", std::to_string(I.pairVirial / gravity));
    RecordProperty("virial_balance_over_gravity_term", std::to_string(balance / gravity));
    EXPECT_GT(I.pairVirial, 0.25 * gravity);  // the pair virial carries most of the balance
    EXPECT_NEAR(balance, 0.0, 0.01 * gravity);
}

TEST(DenseContactCpu, FirstRoundsFromTheMoversFindWhatEveryParticleFinds) {
    // A stage's first impact round looks from the particles fast enough for an impact (collision_
    // resolution.h: startsActive) instead of from every particle: two slower ones cannot meet in one.
    // The 400-ball pile of the tests above, dropped and settled over 3 s, both ways: the same state, bit
    // for bit, the same impacts and the same dissipation.
    struct Outcome {
        uint64_t hash;
        int64_t pairs = 0, walls = 0, rounds = 0;
        int64_t slowAtEnd = 0;  // balls slower than 0.4 times the resting speed after the last step
        double dissipated;
    };
    auto run = [](bool moversFirst) {
        CpuBackendOptions options;
        options.threads = 2;
        options.moversFirst = moversFirst;
        const Scene scene = pileOf400();
        Simulation sim(scene, makeCpuBackend(options), makeInitialState(scene));
        Outcome o{};
        for (int s = 0; s < 720; ++s) {
            const StepReport r = sim.step();
            o.pairs += r.pairCollisions;
            o.walls += r.wallCollisions;
            o.rounds += r.rounds;
        }
        o.hash = stateHash(sim.state());
        o.dissipated = sim.observe().dissipated;
        const double resting = collisionSettingsFor(scene.interaction, scene.integrator.dt, 0.0).restingSpeed;
        for (const Vec3<double>& v : sim.state().velocity) o.slowAtEnd += norm2(v) < 0.16 * resting * resting ? 1 : 0;
        return o;
    };
    const Outcome movers = run(true), everyone = run(false);
    EXPECT_EQ(movers.hash, everyone.hash);
    EXPECT_EQ(movers.pairs, everyone.pairs);
    EXPECT_EQ(movers.walls, everyone.walls);
    EXPECT_EQ(movers.rounds, everyone.rounds);
    EXPECT_EQ(movers.dissipated, everyone.dissipated);
    EXPECT_GT(everyone.pairs, 4000) << "the balls met";
    EXPECT_GT(everyone.slowAtEnd, 200) << "the settled balls start their stages inactive";
}

TEST_P(DenseContact, TheScenesSweepCapBoundsEveryListing) {
    // [interaction] contact_sweeps caps the sweeps of each listing (a game's iteration count): while the
    // pile forms, listings that would run longer stop at the cap, and the conserved sum gains nothing
    // beyond rounding. (It gained 1.4e-8 of itself over these 2 s, and 1.7e-8 uncapped, until a wall
    // impact whose rewind the window cut short no longer turned the ball at the wall plane:
    // AWallPenetrationOlderThanTheStepAddsNoEnergy.)
    Scene scene = pileOf400();
    scene.interaction.contactSweeps = 3;
    auto sim = makeSimulation(backendName(), scene);
    const double conserved0 = sim->observe().conserved();
    int64_t sweeps = 0, listings = 0;
    bool capReached = false;
    for (int s = 0; s < 480; ++s) {
        const StepReport r = sim->step();
        ASSERT_LE(r.contactSweeps, 3 * r.contactListings) << "step " << s;
        capReached = capReached || (r.contactListings == 1 && r.contactSweeps == 3);
        sweeps += r.contactSweeps;
        listings += r.contactListings;
    }
    EXPECT_TRUE(capReached) << "no listing needed the cap: the test does not test it";
    EXPECT_GT(listings, 0);
    EXPECT_LE(sim->observe().conserved(), conserved0 + 1e-12 * std::abs(conserved0)) << sim->observe().conserved() - conserved0;
}

TEST_P(DenseContact, TheScenesListingCapLetsTheLastListingSweepToTheSweepCap) {
    // [interaction] contact_listings caps a step's listings (a game's fixed budget). A listing that is to be
    // listed again stops at 8 sweeps (kRelistSweeps, collision_rounds.cpp); the last one allowed has no
    // listing after it and sweeps on to the cap (16). 300 balls overlapping by up to a third of a diameter
    // (as in OverlapsHandedToTheStageAddNoEnergyAndKeepMomentum) list again without a cap; with a cap of 1
    // or 2 the step lists that often at most and its last listing sweeps past 8. What is left is reported
    // (StepReport::contactOverlap), and the step adds no energy either way.
    auto run = [&](int cap) {
        Scene scene = hardSphereScene(300, 20.0, Method::Verlet, 1e-6);
        scene.interaction.restitution = 0.5;
        scene.interaction.contactListings = cap;
        auto sim = makeSimulation(backendName(), scene, randomOverlaps(3));
        const double before = sim->observe().conserved();
        const StepReport report = sim->step();
        EXPECT_NEAR(sim->observe().conserved(), before, 1e-10) << "cap " << cap;
        return report;
    };
    const StepReport uncapped = run(0);
    ASSERT_GE(uncapped.contactListings, 3) << "the overlaps did not list again twice: the test tests nothing";
    for (const int cap : {1, 2}) {
        const StepReport r = run(cap);
        EXPECT_EQ(r.contactListings, cap);
        EXPECT_GT(r.contactSweeps, 8 * cap) << "cap " << cap << ": the last listing stopped as if listed again";
        EXPECT_LE(r.contactSweeps, 8 * (cap - 1) + 16) << "cap " << cap;
        EXPECT_GT(r.contactOverlap, 0.0) << "cap " << cap << ": what the capped step left is reported";
    }
}

TEST_P(DenseContact, AWallPenetrationOlderThanTheStepAddsNoEnergy) {
    // A ball that starts the step 3.3e-4 inside the floor, moving down: at the step's end its
    // straight-line rewind (4.55e-3) fits the impact window of 1.1 dt (4.58e-3), its parabola's (4.71e-3)
    // does not. The rewind stops at the window, still 7.9e-5 inside; the ball must turn there. Turned at
    // the floor plane, it was lifted by that depth unbooked: the conserved sum rose by m g 7.9e-5.
    Scene scene = hardSphereScene(1, 12.0, Method::Verlet, 1.0 / 240);
    scene.interaction.gravity = {0, -9.81, 0};
    scene.box.wallRestitution = 0.5;
    auto sim = makeSimulation(backendName(), scene, stateOf({{6.0, 0.499667, 6.0}}, {{0, -0.611765, 0}}));
    const double before = sim->observe().conserved();
    const StepReport r = sim->step();
    EXPECT_EQ(r.wallCollisions, 1) << "the penetration is not resolved as an impact: the test does not test it";
    EXPECT_NEAR(sim->observe().conserved(), before, 1e-12 * std::fabs(before));
}
