// The public library API (corebox/corebox.h) through its own header only, on every backend: ids and
// slots, impulses, contacts against the collision counts, the radius query against brute force,
// determinism, placement rejection, the energy balance, the game loop's accumulator, errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <exception>
#include <random>
#include <set>
#include <string>
#include <thread>

#include "corebox/corebox.h"

namespace {

using corebox::ContactKind;
using corebox::ParticleDef;
using corebox::ParticleId;
using corebox::Vec3d;
using corebox::World;
using corebox::WorldDef;

struct Flavour {
    corebox::BackendKind backend;
    corebox::Precision precision;
    const char* name;
    int gpus = 1;  // CUDA: the particles spread over this many GPUs
};

class WorldTest : public ::testing::TestWithParam<Flavour> {
protected:
    WorldDef def() const {
        WorldDef d;
        d.backend = GetParam().backend;
        d.precision = GetParam().precision;
        d.threads = 2;
        d.gpus = GetParam().gpus;
        return d;
    }
    // The world of `d`, or a skip (with the reason) when its backend or GPUs are missing on this machine.
    std::unique_ptr<World> make(const WorldDef& d) {
        try {
            return std::make_unique<World>(d);
        } catch (const corebox::DeviceError& e) {
            m_missing = e.what();
            return nullptr;
        }
    }
    std::string m_missing;
    bool fp64() const { return GetParam().precision == corebox::Precision::Fp64; }
};

#define MAKE_OR_SKIP(world, d)                                                              \
    std::unique_ptr<World> world = make(d);                                                 \
    if (!world) GTEST_SKIP() << GetParam().name << ": not on this machine (DeviceError: " << m_missing << ")"

// n balls on a lattice of spacing 1.5 in the lower middle of the default box, with random velocities.
std::vector<ParticleDef> lattice(int n, unsigned seed, double speed = 2.0) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(-speed, speed);
    std::vector<ParticleDef> out;
    for (int k = 0; k < n; ++k) {
        const int i = k % 12, j = (k / 12) % 12, l = k / 144;
        out.push_back(ParticleDef{0, Vec3d{6 + 1.5 * i, 3 + 1.5 * l, 6 + 1.5 * j}, Vec3d{u(rng), u(rng), u(rng)}});
    }
    return out;
}

void addAll(World& w, const std::vector<ParticleDef>& ps) {
    for (const corebox::PlacementResult& p : w.addParticles(ps)) ASSERT_TRUE(p.placed) << p.reason;
}

// 200 balls at rest on the floor, two layers of 10 x 10 a hair apart (1.05 for a diameter of 1).
std::vector<ParticleDef> heapOf200() {
    std::vector<ParticleDef> heap;
    for (int k = 0; k < 200; ++k)
        heap.push_back(ParticleDef{0, Vec3d{10 + 1.05 * (k % 10), 0.6 + 1.05 * (k / 100), 10 + 1.05 * ((k / 10) % 10)},
                                   Vec3d{0, 0, 0}});
    return heap;
}

// The heap with a column of 8 balls above its middle, falling onto it at `speed`.
std::vector<ParticleDef> heapWithColumn(double speed) {
    std::vector<ParticleDef> balls = heapOf200();
    for (int k = 0; k < 8; ++k) balls.push_back(ParticleDef{0, Vec3d{14.7, 4 + 1.2 * k, 14.7}, Vec3d{0, -speed, 0}});
    return balls;
}

// A definition the World must refuse with an InputError that names `field` (its message says what to change).
void expectRefusedByName(const WorldDef& bad, const std::string& field, const std::string& value) {
    try {
        World w(bad);
        ADD_FAILURE() << field << " = " << value << " was accepted";
    } catch (const corebox::InputError& e) {
        EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
    }
}

TEST_P(WorldTest, IdsStayStableThroughAddsAndRemovals) {
    MAKE_OR_SKIP(w, def());
    addAll(*w, lattice(200, 1));
    // Ids count up from 0 in the order of the adds (world.h): a table indexed by id is a map.
    for (size_t k = 0; k < w->particleCount(); ++k) ASSERT_EQ(w->ids()[k], ParticleId(k));
    for (int s = 0; s < 10; ++s) w->step();
    const std::vector<ParticleId> removed = {0, 77, 199, 5};
    std::map<ParticleId, Vec3d> before;
    for (ParticleId id : w->ids()) before[id] = w->position(id);
    for (ParticleId id : removed) w->removeParticle(id);
    EXPECT_EQ(w->particleCount(), 196u);
    for (ParticleId id : removed) EXPECT_FALSE(w->contains(id));
    EXPECT_THROW(w->removeParticle(77), corebox::InputError);
    // The others keep their ids and states, wherever their slots went.
    for (const auto& [id, x] : before) {
        if (std::find(removed.begin(), removed.end(), id) != removed.end()) continue;
        ASSERT_TRUE(w->contains(id));
        EXPECT_EQ(w->position(id).x, x.x);
        EXPECT_EQ(w->position(id).y, x.y);
        EXPECT_EQ(w->position(id).z, x.z);
    }
    // A new particle gets a new id, never a removed one.
    const corebox::PlacementResult added = w->addParticle({0, {25, 50, 25}, {0, 0, 0}});
    ASSERT_TRUE(added.placed) << added.reason;
    EXPECT_EQ(added.id, 200u);
    std::set<ParticleId> unique(w->ids().begin(), w->ids().end());
    EXPECT_EQ(unique.size(), w->particleCount());

    // States stay consistent: the world after edits steps exactly as a world built directly from the
    // same particles in the same slot order.
    std::vector<ParticleDef> same;
    for (size_t k = 0; k < w->particleCount(); ++k) same.push_back({w->speciesIndices()[k], w->positions()[k], w->velocities()[k]});
    MAKE_OR_SKIP(fresh, def());
    addAll(*fresh, same);
    for (int s = 0; s < 20; ++s) {
        w->step();
        fresh->step();
    }
    for (size_t k = 0; k < w->particleCount(); ++k) {
        EXPECT_EQ(w->positions()[k].y, fresh->positions()[k].y) << "slot " << k;
        EXPECT_EQ(w->velocities()[k].x, fresh->velocities()[k].x) << "slot " << k;
    }
    // Removing every particle empties the world; it steps and fills again.
    const std::vector<ParticleId> all(w->ids().begin(), w->ids().end());
    for (ParticleId id : all) w->removeParticle(id);
    EXPECT_EQ(w->particleCount(), 0u);
    w->step();
    EXPECT_TRUE(w->addParticle({0, {15, 30, 15}, {0, 0, 0}}).placed);
    w->step();
    EXPECT_EQ(w->particleCount(), 1u);
}

TEST_P(WorldTest, ImpulseChangesMomentumByExactlyJ) {
    WorldDef d = def();
    d.gravity = {0, 0, 0};
    d.species.front().mass = 2.0;
    MAKE_OR_SKIP(w, d);
    addAll(*w, lattice(50, 2));
    const Vec3d p0 = w->energy().momentum;
    const Vec3d j{1.25, -2.5, 0.75};
    w->applyImpulse(7, j);
    w->applyImpulse(8, Vec3d{-j.x, -j.y, -j.z});
    w->applyImpulse(9, j);
    const Vec3d p1 = w->energy().momentum;
    // Rounding of v + J/m in the backend's precision and of the momentum sum over 50 particles.
    const double tol = fp64() ? 1e-12 : 1e-5;
    EXPECT_NEAR(p1.x - p0.x, j.x, tol);
    EXPECT_NEAR(p1.y - p0.y, j.y, tol);
    EXPECT_NEAR(p1.z - p0.z, j.z, tol);
    // Per particle: the velocity changes by J / m.
    const Vec3d v = w->velocity(20);
    w->applyImpulse(20, j);
    EXPECT_NEAR(w->velocity(20).x - v.x, j.x / 2.0, fp64() ? 1e-15 : 1e-6);
}

TEST_P(WorldTest, ContactsMatchTheCollisionsCounted) {
    MAKE_OR_SKIP(w, def());
    addAll(*w, lattice(400, 3, 6.0));
    int64_t pairs = 0, walls = 0;
    for (int s = 0; s < 300; ++s) {
        const corebox::StepInfo info = w->step();
        int64_t p = 0, q = 0;
        for (const corebox::Contact& c : w->contacts()) {
            ASSERT_TRUE(w->contains(c.a));
            EXPECT_NEAR(std::sqrt(c.normal.x * c.normal.x + c.normal.y * c.normal.y + c.normal.z * c.normal.z), 1.0, 1e-5);
            EXPECT_GE(c.time, 0.0);
            EXPECT_LE(c.time, 1.0 / 240.0 + 1e-12);
            EXPECT_GE(c.impulse, 0.0);
            if (c.kind == ContactKind::Pair) {
                ++p;
                ASSERT_TRUE(w->contains(c.b));
                EXPECT_NE(c.a, c.b);
            } else {
                ++q;
                EXPECT_EQ(c.b, corebox::kNoParticle);
                EXPECT_TRUE(c.wallAxis >= 0 && c.wallAxis < 3 && (c.wallSide == 0 || c.wallSide == 1));
            }
        }
        ASSERT_EQ(p, info.pairCollisions) << "step " << s;
        ASSERT_EQ(q, info.wallCollisions) << "step " << s;
        pairs += p;
        walls += q;
    }
    EXPECT_GT(pairs, 100);
    EXPECT_GT(walls, 100);
}

// WorldDef::contactMinImpulse: the same world with a threshold lists exactly the impacts of the world
// without one whose impulse reaches it, in the same order, and steps to the same state.
TEST_P(WorldTest, ContactMinImpulseListsTheStrongImpactsOnly) {
    WorldDef all = def(), strong = def();
    strong.contactMinImpulse = 2.7;  // not a float: the threshold is compared in double on every backend
    MAKE_OR_SKIP(a, all);
    MAKE_OR_SKIP(b, strong);
    addAll(*a, lattice(400, 3, 6.0));
    addAll(*b, lattice(400, 3, 6.0));
    int64_t kept = 0, dropped = 0;
    for (int s = 0; s < 300; ++s) {
        a->step();
        b->step();
        std::vector<corebox::Contact> expected;
        for (const corebox::Contact& c : a->contacts()) {
            if (std::abs(c.impulse) >= strong.contactMinImpulse) expected.push_back(c);
            else ++dropped;
        }
        const std::vector<corebox::Contact>& got = b->contacts();
        ASSERT_EQ(got.size(), expected.size()) << "step " << s;
        for (size_t k = 0; k < got.size(); ++k) {
            EXPECT_EQ(got[k].a, expected[k].a);
            EXPECT_EQ(got[k].b, expected[k].b);
            EXPECT_EQ(got[k].impulse, expected[k].impulse);
        }
        kept += int64_t(got.size());
    }
    EXPECT_EQ(a->stateHash(), b->stateHash());
    EXPECT_GT(kept, 50);
    EXPECT_GT(dropped, 50);
    WorldDef bad = def();
    bad.contactMinImpulse = -1;
    EXPECT_THROW(World{bad}, corebox::InputError);
}

TEST_P(WorldTest, HeadOnImpactIsReportedExactly) {
    WorldDef d = def();
    d.gravity = {0, 0, 0};
    d.restitution = 1.0;
    MAKE_OR_SKIP(w, d);
    // Centres 2.1 apart closing at 2: the gap of 1.1 closes at t = 0.55, 0.05 into the sixth step of 0.1.
    const ParticleId a = w->addParticle({0, {14, 30, 15}, {1, 0, 0}}).id;
    const ParticleId b = w->addParticle({0, {16.1, 30, 15}, {-1, 0, 0}}).id;
    int seen = 0;
    for (int s = 0; s < 8; ++s) {
        w->step(0.1);
        for (const corebox::Contact& c : w->contacts()) {
            ++seen;
            EXPECT_EQ(c.kind, ContactKind::Pair);
            EXPECT_EQ(std::min(c.a, c.b), a);
            EXPECT_EQ(std::max(c.a, c.b), b);
            EXPECT_NEAR(c.impulse, 2.0, 1e-5);  // (1 + e) mu v_n = 2 * 0.5 * 2
            EXPECT_NEAR(c.speed, 2.0, 1e-5);
            EXPECT_NEAR(std::fabs(c.normal.x), 1.0, 1e-6);
            EXPECT_EQ(s, 5);
            EXPECT_NEAR(c.time, 0.05, 1e-5);
        }
    }
    EXPECT_EQ(seen, 1);
    EXPECT_NEAR(w->velocity(a).x, -1.0, 1e-5);
    EXPECT_NEAR(w->velocity(b).x, 1.0, 1e-5);
}

TEST_P(WorldTest, RadiusQueryEqualsBruteForce) {
    MAKE_OR_SKIP(w, def());
    addAll(*w, lattice(600, 4, 4.0));
    std::mt19937_64 rng(5);
    // Centres up to 5 outside the box too: a query there still finds the balls near the walls.
    std::uniform_real_distribution<double> ux(-5, 35), uy(-5, 65), ur(0, 6);
    for (int round = 0; round < 3; ++round) {
        for (int q = 0; q < 50; ++q) {
            const Vec3d c{ux(rng), uy(rng), ux(rng)};
            const double r = ur(rng);
            std::vector<ParticleId> brute;
            for (size_t k = 0; k < w->particleCount(); ++k) {
                const Vec3d x = w->positions()[k];
                if ((x.x - c.x) * (x.x - c.x) + (x.y - c.y) * (x.y - c.y) + (x.z - c.z) * (x.z - c.z) <= r * r)
                    brute.push_back(w->ids()[k]);
            }
            std::sort(brute.begin(), brute.end());
            EXPECT_EQ(w->queryRadius(c, r), brute);
        }
        for (int s = 0; s < 50; ++s) w->step();
        w->removeParticle(w->ids()[round]);
    }
    // A box of 10^12 of the balls' cells holding three balls: the grid's cells grow instead of its memory.
    WorldDef wide = def();
    wide.boxSize = Vec3d{1e4, 1e4, 1e4};
    MAKE_OR_SKIP(v, wide);
    addAll(*v, {ParticleDef{0, Vec3d{1, 1, 1}, Vec3d{0, 0, 0}}, ParticleDef{0, Vec3d{5000, 2, 5000}, Vec3d{0, 0, 0}},
                ParticleDef{0, Vec3d{9999, 9999, 9999}, Vec3d{0, 0, 0}}});
    EXPECT_FALSE(v->addParticle({0, {1.5, 1.2, 1.1}, {0, 0, 0}}).placed) << "overlaps the first ball";
    EXPECT_EQ(v->queryRadius({5000, 2, 5000}, 0.1), (std::vector<ParticleId>{1}));
    EXPECT_EQ(v->queryRadius({1e4 + 3, 1e4, 1e4}, 5), (std::vector<ParticleId>{2}));
    EXPECT_EQ(v->queryRadius({0, 0, 0}, 2e4).size(), 3u);
}

TEST_P(WorldTest, SameCallsGiveTheSameHash) {
    auto run = [&](std::unique_ptr<World>& w) {
        addAll(*w, lattice(300, 6, 5.0));
        for (int f = 0; f < 30; ++f) {
            w->advance(1.0 / 60.0);
            if (f == 10) w->applyImpulse(3, {0, 40, 0});
            if (f == 15) w->removeParticle(17);
            if (f == 20) (void)w->addParticle({0, {15, 55, 15}, {0, -3, 0}});
        }
        return w->stateHash();
    };
    MAKE_OR_SKIP(first, def());
    MAKE_OR_SKIP(second, def());
    const uint64_t h1 = run(first), h2 = run(second);
    EXPECT_EQ(h1, h2);
    second->step();
    EXPECT_NE(second->stateHash(), h1);
}

// positions() after a step downloads the positions alone (a renderer's read); the velocities stay stale
// until something needs them. An edit then must first bring them up to date, since flushEdits uploads the
// whole mirror: a world that reads positions() every frame before its edits gives the bits of one that
// reads velocities() (the whole mirror). Fails if an edit uploaded the velocities of an older download.
TEST_P(WorldTest, ReadingPositionsAloneKeepsEditsWhole) {
    auto run = [&](std::unique_ptr<World>& w, bool positionsAlone) {
        addAll(*w, lattice(300, 8, 5.0));
        double sum = 0;
        for (int f = 0; f < 24; ++f) {
            w->advance(1.0 / 60.0);
            for (const Vec3d& x : positionsAlone ? w->positions() : w->velocities()) sum += x.y;
            if (f == 4) w->applyImpulse(3, {0, 40, 0});
            if (f == 8) w->setVelocity(5, {1, 2, 3});
            if (f == 12) EXPECT_TRUE(w->setPosition(7, {20, 50, 20}).placed);
            if (f == 16) w->removeParticle(17);
            if (f == 20) (void)w->addParticle({0, {15, 55, 15}, {0, -3, 0}});
        }
        EXPECT_TRUE(std::isfinite(sum));
        return w->stateHash();
    };
    MAKE_OR_SKIP(positionsAlone, def());
    MAKE_OR_SKIP(whole, def());
    EXPECT_EQ(run(positionsAlone, true), run(whole, false));
    const corebox::Span<Vec3d> x = positionsAlone->positions(), y = whole->positions();
    ASSERT_EQ(x.size, y.size);
    size_t differ = 0;
    for (size_t k = 0; k < x.size; ++k) differ += x[k].x != y[k].x || x[k].y != y[k].y || x[k].z != y[k].z;
    EXPECT_EQ(differ, 0u) << "positions that differ, of " << x.size;
}

// A species added after steps is an edit like any other (the next step uploads the mirror): it must not
// take the particles back to the mirror's last download, whether nothing was read since the steps or the
// positions alone were. A world that adds an unused species steps on as one that does not. Fails if
// addSpecies uploads a stale mirror (the balls jump back by up to a ball's size).
TEST_P(WorldTest, AddingASpeciesAfterStepsKeepsTheState) {
    for (const bool readPositions : {false, true}) {
        auto run = [&](std::unique_ptr<World>& w, bool addSpecies) {
            addAll(*w, lattice(300, 9, 5.0));
            for (int f = 0; f < 15; ++f) {
                w->advance(1.0 / 60.0);
                if (f == 5) (void)w->velocities();  // a whole download, older than what follows
                if (f == 9 && readPositions) (void)w->positions();
                if (f == 9 && addSpecies) {
                    corebox::ParticleSpecies unused;
                    unused.name = "unused";
                    (void)w->addSpecies(unused);
                }
            }
            return w->stateHash();
        };
        MAKE_OR_SKIP(adding, def());
        MAKE_OR_SKIP(plain, def());
        EXPECT_EQ(run(adding, true), run(plain, false))
            << (readPositions ? "positions read before" : "nothing read before");
    }
}

// The sandbox steps its world on a worker thread and edits and reads it on the main one. A world
// driven from a new thread for every frame gives the bits of one driven from one thread; on CUDA the
// world sits on device 1 where there is one, and the new threads start on device 0. This checks the
// result, not World::Impl::bindThread itself: with bindThread emptied the test still passed on two
// H200s, since the CUDA backend's step and copy paths select their GPUs themselves; bindThread is what
// keeps world.h's promise that the world's device is current after a call.
TEST_P(WorldTest, AnyThreadMayDriveTheWorldOneCallAtATime) {
    WorldDef d = def();
    if (GetParam().backend == corebox::BackendKind::Cuda && GetParam().gpus == 1) {
        d.device = 1;
        if (!make(d)) d.device = 0;
    }
    auto run = [&](World& w, bool threaded) {
        addAll(w, lattice(300, 6, 5.0));
        for (int f = 0; f < 30; ++f) {
            auto frame = [&] {
                w.advance(1.0 / 60.0);
                (void)w.positions();
            };
            if (threaded) {
                std::exception_ptr error;
                std::thread([&] {
                    try {
                        frame();
                    } catch (...) {
                        error = std::current_exception();
                    }
                }).join();
                if (error) std::rethrow_exception(error);
            } else {
                frame();
            }
            if (f == 10) w.applyImpulse(3, {0, 40, 0});
            if (f == 15) w.removeParticle(17);
            if (f == 20) (void)w.addParticle({0, {15, 55, 15}, {0, -3, 0}});
        }
        return w.stateHash();
    };
    MAKE_OR_SKIP(one, d);
    MAKE_OR_SKIP(many, d);
    const uint64_t h1 = run(*one, false);
    const uint64_t h2 = run(*many, true);
    EXPECT_EQ(h1, h2) << "device " << d.device;
    EXPECT_GT(many->energy().kinetic, 0.0);
}

TEST_P(WorldTest, OverlappingPlacementsAreRejectedAndReported) {
    MAKE_OR_SKIP(w, def());
    const ParticleId a = w->addParticle({0, {10, 10, 10}, {0, 0, 0}}).id;
    const corebox::PlacementResult over = w->addParticle({0, {10.6, 10, 10}, {0, 0, 0}});
    EXPECT_FALSE(over.placed);
    EXPECT_EQ(over.blockedBy, a);
    EXPECT_EQ(over.id, corebox::kNoParticle);
    EXPECT_NE(over.reason.find("overlap"), std::string::npos) << over.reason;
    const corebox::PlacementResult wall = w->addParticle({0, {0.3, 10, 10}, {0, 0, 0}});
    EXPECT_FALSE(wall.placed);
    EXPECT_NE(wall.reason.find("wall"), std::string::npos) << wall.reason;
    const corebox::PlacementResult unknown = w->addParticle({3, {20, 10, 10}, {0, 0, 0}});
    EXPECT_FALSE(unknown.placed);
    EXPECT_EQ(w->particleCount(), 1u);
    // Touching is not overlapping.
    const ParticleId b = w->addParticle({0, {11, 10, 10}, {0, 0, 0}}).id;
    ASSERT_NE(b, corebox::kNoParticle);
    // A teleport onto another is refused and leaves the particle where it was.
    const corebox::PlacementResult moved = w->setPosition(b, {10.2, 10.1, 10});
    EXPECT_FALSE(moved.placed);
    EXPECT_EQ(moved.blockedBy, a);
    EXPECT_EQ(w->position(b).x, 11.0);
    EXPECT_TRUE(w->setPosition(b, {20, 10, 10}).placed);
    EXPECT_EQ(w->position(b).x, 20.0);
    // A bigger species added later is checked with its own radius.
    corebox::ParticleSpecies big;
    big.name = "big";
    big.radius = 2.0;
    big.mass = 10;
    const int s = w->addSpecies(big);
    EXPECT_FALSE(w->addParticle({s, {12.3, 10, 10}, {0, 0, 0}}).placed);
    const corebox::PlacementResult fits = w->addParticle({s, {15, 10, 10}, {0, 0, 0}});
    EXPECT_TRUE(fits.placed) << fits.reason;
    w->step();
}

TEST_P(WorldTest, EnergyBalanceClosesThroughEdits) {
    MAKE_OR_SKIP(w, def());
    addAll(*w, lattice(500, 7, 3.0));
    double scale = 0;
    for (int f = 0; f < 120; ++f) {
        w->advance(1.0 / 60.0);
        if (f == 20) w->applyImpulse(5, {0, 30, 0});
        if (f == 40) w->removeParticle(100);
        if (f == 50) (void)w->addParticle({0, {15, 55, 15}, {2, 0, 0}});
        if (f == 60) w->setGravity({0, -5, 1});
        if (f == 70) w->setSpeciesAcceleration(0, {0.5, 0, 0});
        if (f == 80) (void)w->setPosition(200, {15, 50, 5});
        const corebox::EnergyBalance e = w->energy();
        scale = std::max(scale, std::fabs(e.kinetic) + std::fabs(e.potential));
    }
    const corebox::EnergyBalance e = w->energy();
    EXPECT_GT(e.dissipated, 0.0);
    // Verlet under uniform fields is exact between impacts; what is left is the contact solver's
    // and rounding's share, 1e-6 of the energy scale in fp64 (fp32 states round at 1e-7 of a length).
    EXPECT_LT(std::fabs(e.conserved()), (fp64() ? 1e-6 : 1e-3) * scale) << "K " << e.kinetic << " U " << e.potential << " D "
                                                                         << e.dissipated << " W " << e.external;
}

TEST_P(WorldTest, SpeciesAccelerationsAddToGravity) {
    MAKE_OR_SKIP(w, def());
    corebox::ParticleSpecies balloon;
    balloon.name = "balloon";
    balloon.acceleration = {0, 9.81, 0};  // buoyancy cancels gravity: it floats
    const int s = w->addSpecies(balloon);
    const ParticleId stone = w->addParticle({0, {10, 30, 15}, {0, 0, 0}}).id;
    const ParticleId floating = w->addParticle({s, {20, 30, 15}, {0, 0, 0}}).id;
    for (int f = 0; f < 60; ++f) w->advance(1.0 / 60.0);
    const double tol = fp64() ? 1e-9 : 1e-4;
    EXPECT_NEAR(w->position(stone).y, 30 - 0.5 * 9.81, tol);  // Verlet is exact under a uniform field
    EXPECT_NEAR(w->position(floating).y, 30, tol);
    w->setSpeciesAcceleration(s, {1, 9.81, 0});  // now a wind along x for the balloon alone
    for (int f = 0; f < 60; ++f) w->advance(1.0 / 60.0);
    EXPECT_NEAR(w->position(floating).x, 20.5, tol);
    EXPECT_NEAR(w->position(stone).x, 10, tol);
    // The field's potential is in the balance: -m a.x summed with each species' own field.
    const corebox::EnergyBalance e = w->energy();
    // fp32: rounding of potentials near m g y = 300 at a relative 1e-7 per step.
    EXPECT_NEAR(e.conserved(), 0.0, fp64() ? 1e-9 : 1e-5 * 600);
}

TEST_P(WorldTest, DeviceStateNamesWhereTheStateLives) {
    MAKE_OR_SKIP(w, def());
    EXPECT_EQ(w->deviceState().count, 0);  // an empty world has no simulation yet
    addAll(*w, lattice(100, 9));
    w->step();
    const corebox::DeviceState d = w->deviceState();
    if (GetParam().backend == corebox::BackendKind::Cpu) {
        EXPECT_EQ(d.device, -1);
        EXPECT_EQ(d.position, nullptr);
        return;
    }
    EXPECT_GE(d.device, 0);
    EXPECT_EQ(d.count, 100);
    EXPECT_EQ(d.precision, GetParam().precision);
    EXPECT_NE(d.position, nullptr);
    EXPECT_NE(d.velocity, nullptr);
    EXPECT_NE(d.species, nullptr);
    EXPECT_NE(w->backendName().find("cuda"), std::string::npos);
}

TEST_P(WorldTest, AdvanceKeepsAFixedSubstep) {
    MAKE_OR_SKIP(w, def());
    addAll(*w, lattice(10, 8));
    corebox::StepInfo info = w->advance(1.0 / 60.0);
    EXPECT_EQ(info.substeps, 4);
    EXPECT_NEAR(info.alpha, 0.0, 1e-9);
    info = w->advance(0.5 / 240.0);
    EXPECT_EQ(info.substeps, 0);
    EXPECT_NEAR(info.alpha, 0.5, 1e-9);
    info = w->advance(1.0);  // a stall: at most 8 substeps, the rest dropped
    EXPECT_EQ(info.substeps, 8);
    EXPECT_NEAR(info.droppedTime + info.substeps / 240.0 + info.alpha / 240.0, 1.0 + 0.5 / 240.0, 1e-9);
    EXPECT_EQ(w->stepCount(), 12);
    EXPECT_NEAR(w->time(), 12 / 240.0, 1e-12);
    EXPECT_THROW(w->advance(-1.0), corebox::InputError);
}

TEST_P(WorldTest, BadInputThrowsWithAMessage) {
    WorldDef d = def();
    d.species.front().mass = -1;
    try {
        World w(d);
        FAIL() << "a negative mass was accepted";
    } catch (const corebox::InputError& e) {
        EXPECT_NE(std::string(e.what()).find("mass"), std::string::npos) << e.what();
    } catch (const corebox::DeviceError&) {
        GTEST_SKIP() << GetParam().name << ": no CUDA device here";
    }
    d = def();
    d.method = "leapfrogg";
    EXPECT_THROW(World{d}, std::exception);
    MAKE_OR_SKIP(w, def());
    EXPECT_THROW(w->applyImpulse(12345, {1, 0, 0}), corebox::InputError);
    EXPECT_THROW(w->setRestitution(1.5, 0.5), corebox::InputError);
    EXPECT_THROW(w->step(-0.1), corebox::InputError);
    EXPECT_THROW(w->species(4), corebox::InputError);
}

// WorldDef::contactSweeps reaches the contact solver: a heap dropped on the floor rests differently
// with one sweep a listing than with corebox's own cap, and a negative cap is refused by name.
TEST_P(WorldTest, ContactSweepsCapTheSolver) {
    auto heap = [&](int sweeps) {
        WorldDef d = def();
        d.contactSweeps = sweeps;
        std::unique_ptr<World> w = make(d);
        if (!w) return uint64_t(0);
        addAll(*w, heapOf200());
        for (int f = 0; f < 30; ++f) w->advance(1.0 / 60.0);
        return w->stateHash();
    };
    const uint64_t own = heap(0);
    if (own == 0) GTEST_SKIP() << GetParam().name << ": not on this machine (DeviceError: " << m_missing << ")";
    EXPECT_NE(heap(1), own);
    EXPECT_EQ(heap(16), own);  // corebox's own cap is 16
    WorldDef bad = def();
    bad.contactSweeps = -1;
    expectRefusedByName(bad, "contactSweeps", "-1");
}

// WorldDef::impactRounds reaches the impact rounds: a column of balls falling onto a heap takes more
// than one round a step (each impact of a chain turns the next ball), so a cap of one is hit, corebox's
// own cap (64) is 0's, and a negative cap or one above 4096 is refused by name.
TEST_P(WorldTest, ImpactRoundsCapTheRounds) {
    auto drop = [&](int rounds, int* capHits) {
        WorldDef d = def();
        d.impactRounds = rounds;
        std::unique_ptr<World> w = make(d);
        if (!w) return uint64_t(0);
        addAll(*w, heapWithColumn(6));
        *capHits = 0;
        for (int f = 0; f < 30; ++f) *capHits += w->advance(1.0 / 60.0).roundCapHits;
        return w->stateHash();
    };
    int ownHits = 0, oneHits = 0, sixtyFourHits = 0;
    const uint64_t own = drop(0, &ownHits);
    if (own == 0) GTEST_SKIP() << GetParam().name << ": not on this machine (DeviceError: " << m_missing << ")";
    EXPECT_EQ(ownHits, 0);
    EXPECT_NE(drop(1, &oneHits), own);
    EXPECT_GT(oneHits, 0);
    EXPECT_EQ(drop(64, &sixtyFourHits), own);  // corebox's own cap is 64
    WorldDef bad = def();
    for (const int rounds : {-1, 4097}) {  // at most 4096: a GPU keeps and clears two counters a round
        bad.impactRounds = rounds;
        expectRefusedByName(bad, "impactRounds", std::to_string(rounds));
    }
}

// WorldDef::contactListings caps the contact solver's listings a step: a column fired into a heap with one
// impact round a step leaves its impacts to the contact phase, overlaps deeper than 2% of a diameter, which
// corebox's own cap lists again; a cap of one lists once a step at most and ends elsewhere; 32 is 0's; StepInfo
// reports the listings and the overlap left; a cap below 0 or above 32 is refused by name.
TEST_P(WorldTest, ContactListingsCapTheSolver) {
    struct Run {
        uint64_t hash = 0;
        int mostListings = 0;
        double overlapLeft = -1;
    };
    auto drop = [&](int listings) {
        WorldDef d = def();
        d.impactRounds = 1;
        d.contactListings = listings;
        std::unique_ptr<World> w = make(d);
        Run run;
        if (!w) return run;
        addAll(*w, heapWithColumn(12));
        for (int s = 0; s < 120; ++s) {
            const corebox::StepInfo info = w->step(1.0 / 240.0);
            run.mostListings = std::max(run.mostListings, info.contactListings);
            run.overlapLeft = std::max(run.overlapLeft, info.overlapLeft);
        }
        run.hash = w->stateHash();
        return run;
    };
    const Run own = drop(0);
    if (own.hash == 0) GTEST_SKIP() << GetParam().name << ": not on this machine (DeviceError: " << m_missing << ")";
    EXPECT_GE(own.mostListings, 2);
    EXPECT_GT(own.overlapLeft, 0.0);   // the pile's contacts leave some overlap: reported
    EXPECT_LT(own.overlapLeft, 0.02);  // corebox's own cap lists until the overlaps start below 2%
    const Run one = drop(1);
    EXPECT_EQ(one.mostListings, 1);
    EXPECT_NE(one.hash, own.hash);
    EXPECT_EQ(drop(32).hash, own.hash);  // corebox's own cap is 32
    WorldDef bad = def();
    for (const int listings : {-1, 33}) {
        bad.contactListings = listings;
        expectRefusedByName(bad, "contactListings", std::to_string(listings));
    }
}

TEST_P(WorldTest, StepInfoSplitsTheCollisionStagesTime) {
    MAKE_OR_SKIP(w, def());
    addAll(*w, heapOf200());
    double impacts = 0, contacts = 0, listings = 0;
    for (int f = 0; f < 20; ++f) {
        const corebox::StepInfo info = w->advance(1.0 / 60.0);
        EXPECT_GE(info.secondsImpacts, 0.0);
        EXPECT_GE(info.secondsListings, 0.0);
        EXPECT_LE(info.secondsListings, info.secondsContacts);
        EXPECT_LE(info.secondsImpacts + info.secondsContacts, info.seconds);
        impacts += info.secondsImpacts;
        contacts += info.secondsContacts;
        listings += info.secondsListings;
    }
    // Wired through: each part reached StepInfo (a heap on the floor is screened, listed and relaxed).
    EXPECT_GT(impacts, 0.0);
    EXPECT_GT(listings, 0.0);
    EXPECT_GT(contacts, listings);
}

// 300 balls dropped into a narrow box (6 x 30 x 6) from a jittered lattice: a heap about nine layers
// deep once settled, its contacts disordered. `far` first adds a ball near the top (id 0), dropped
// from rest: it falls about 11 of the box's 30 in the 90 frames, never near the heap.
std::vector<ParticleDef> heapBalls(bool far) {
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> jitter(-0.04, 0.04);
    std::vector<ParticleDef> balls;
    if (far) balls.push_back(ParticleDef{0, Vec3d{5.4, 29.4, 5.4}, Vec3d{0, 0, 0}});
    for (int k = 0; k < 300; ++k)
        balls.push_back(ParticleDef{0, Vec3d{0.7 + 1.1 * (k % 5) + jitter(rng), 0.6 + 1.1 * (k / 25), 0.7 + 1.1 * ((k / 5) % 5) + jitter(rng)},
                                    Vec3d{0, 0, 0}});
    return balls;
}

// The heap's balls (ids first .. first + 299) after a frame, in id order.
std::vector<Vec3d> heapAfterAFrame(World& w, ParticleId first) {
    w.advance(1.0 / 60.0);
    std::vector<Vec3d> out;
    for (ParticleId id = first; id < first + 300; ++id) out.push_back(w.position(id));
    return out;
}

// Edits upload the whole state, and a backend forgets the contact impulses that warm-start its next
// contact phase when handed a state; the world carries them over to the particles' new slots, with the
// colours the CUDA backend keeps between fresh colourings (ContactCarryOver). Adding a ball far away
// then changes nothing of the heap's next frame, bit for bit; removing one, which moves the last slot
// into its place, changes only the order of the work (checked on the CPU, below).
TEST_P(WorldTest, EditsKeepARestingHeapsContactImpulses) {
    WorldDef d = def();
    d.boxSize = Vec3d{6, 30, 6};
    auto settled = [&](bool far) {
        std::unique_ptr<World> w = make(d);
        if (!w) return w;
        addAll(*w, heapBalls(far));
        for (int f = 0; f < 90; ++f) w->advance(1.0 / 60.0);
        w->step();  // 361 steps: the step after the edit keeps the last step's colours (every 4th colours afresh)
        return w;
    };
    std::unique_ptr<World> plain = settled(false);
    if (!plain) GTEST_SKIP() << GetParam().name << ": not on this machine (DeviceError: " << m_missing << ")";
    std::unique_ptr<World> added = settled(false);
    ASSERT_TRUE(added->addParticle({0, {5.4, 29.4, 5.4}, {0, 0, 0}}).placed);
    const std::vector<Vec3d> a = heapAfterAFrame(*plain, 0), b = heapAfterAFrame(*added, 0);
    for (size_t k = 0; k < a.size(); ++k) {
        ASSERT_EQ(a[k].x, b[k].x) << "ball " << k;
        ASSERT_EQ(a[k].y, b[k].y) << "ball " << k;
        ASSERT_EQ(a[k].z, b[k].z) << "ball " << k;
    }

    // On CUDA a removal renumbers the rows, and so the colours of the sweeps: another order of the
    // unconverged sweeps moves the heap by about 1e-3 (fp64 and fp32, an H200) with the impulses carried
    // or not, which would hide them. The remapping is the world's, the same for every backend, and the
    // CPU's bottom-up order depends on the numbering far less (below).
    if (GetParam().backend != corebox::BackendKind::Cpu) return;
    std::unique_ptr<World> kept = settled(true), removed = settled(true);
    removed->removeParticle(0);  // the heap's last ball takes slot 0
    const std::vector<Vec3d> c = heapAfterAFrame(*kept, 1), e = heapAfterAFrame(*removed, 1);
    double moved = 0;
    for (size_t k = 0; k < c.size(); ++k)
        moved = std::max({moved, std::fabs(c[k].x - e[k].x), std::fabs(c[k].y - e[k].y), std::fabs(c[k].z - e[k].z)});
    // The new numbering still changes something of the order of the work, and the sweeps stop at
    // their cap before they converge: 7e-6 here (fp64 and fp32). Without the impulses carried the heap
    // moved 1e-3.
    EXPECT_LT(moved, 1e-4);
}

TEST(WorldScene, ASceneFileBecomesAWorld) {
    World w = World::fromSceneFile(std::string(COREBOX_SOURCE_DIR) + "/assets/pile.toml");
    EXPECT_EQ(w.particleCount(), 10000u);
    EXPECT_EQ(w.ids()[9999], 9999u);
    w.step();
    EXPECT_EQ(w.stepCount(), 1);
    EXPECT_THROW(World::fromSceneFile("/nonexistent/scene.toml"), corebox::InputError);
}

TEST(WorldVersion, IsTheProjectVersion) { EXPECT_STREQ(corebox::version(), COREBOX_VERSION_EXPECTED); }

INSTANTIATE_TEST_SUITE_P(Backends, WorldTest,
                         ::testing::Values(Flavour{corebox::BackendKind::Cpu, corebox::Precision::Fp64, "cpu_fp64"},
                                           Flavour{corebox::BackendKind::Cpu, corebox::Precision::Fp32, "cpu_fp32"},
                                           Flavour{corebox::BackendKind::Cuda, corebox::Precision::Fp64, "cuda_fp64"},
                                           Flavour{corebox::BackendKind::Cuda, corebox::Precision::Fp32, "cuda_fp32"},
                                           Flavour{corebox::BackendKind::Cuda, corebox::Precision::Fp64, "cuda2_fp64", 2},
                                           Flavour{corebox::BackendKind::Cuda, corebox::Precision::Fp32, "cuda2_fp32", 2}),
                         [](const ::testing::TestParamInfo<Flavour>& info) { return std::string(info.param.name); });

}  // namespace
