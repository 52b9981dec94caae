// corebox_bullet_pile: the ball pile of `corebox bench pile` run in Bullet, the peer a game programmer
// would reach for, so that both engines are timed on the same machine in the same run.
//
// Design note. The benchmark writes the initial state with corebox's state CSV writer and runs this
// program on it; the program prints one JSON object on stdout with the same measures
// (pile_measures.h) that the benchmark takes of corebox. Bullet is set up as a game would use it, and
// as the issue that asked for the comparison did: btDiscreteDynamicsWorld, btDbvtBroadphase, the
// sequential impulse solver with its defaults (10 iterations, split impulse), one thread; spheres of
// radius 0.5 and mass 1 with no friction and no rolling friction; six static planes for the walls.
// Bullet multiplies the restitution of the two bodies in contact, so every body, walls included, gets
// sqrt(e) and every contact e. Deactivation (sleeping) is disabled, so every ball is simulated every
// step as in corebox. Frames are stepSimulation(1/60, substeps, 1/(60 substeps)); an internal tick
// callback counts the fixed steps actually taken, since Bullet's time accumulator in float may take
// one fewer or one more in a frame. Energy is kinetic (with the rotational part, zero without friction)
// plus m g z; Bullet does not report what its contacts dissipate, so its energy balance has no
// dissipated term and must simply fall.
#include <btBulletDynamicsCommon.h>

#include <CLI/CLI.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "bench_scenes.h"
#include "errors.h"
#include "pile_measures.h"
#include "state_csv.h"

namespace {

using namespace corebox;

struct DriverOptions {
    std::string statePath;
    std::vector<double> box{kPile.box[0], kPile.box[1], kPile.box[2]};
    double radius = kPile.radius;
    double mass = kPile.mass;
    double gravity = kPile.gravity;  // along -z
    double restitution = kPile.restitution;
    double wallRestitution = kPile.wallRestitution;
    double seconds = 5.0;
    int substeps = 4;
};

struct PileWorld {
    btDefaultCollisionConfiguration configuration;
    btCollisionDispatcher dispatcher{&configuration};
    btDbvtBroadphase broadphase;
    btSequentialImpulseConstraintSolver solver;
    btDiscreteDynamicsWorld world{&dispatcher, &broadphase, &solver, &configuration};
    std::unique_ptr<btSphereShape> sphere;
    std::vector<std::unique_ptr<btStaticPlaneShape>> planeShapes;
    std::vector<std::unique_ptr<btDefaultMotionState>> motionStates;
    std::vector<std::unique_ptr<btRigidBody>> bodies;  // walls first, then the balls
    std::vector<btRigidBody*> balls;
    int64_t ticks = 0;

    ~PileWorld() {
        for (const std::unique_ptr<btRigidBody>& body : bodies) world.removeRigidBody(body.get());
    }
};

void countTick(btDynamicsWorld* world, btScalar) { ++static_cast<PileWorld*>(world->getWorldUserInfo())->ticks; }

btRigidBody* addBody(PileWorld& w, btCollisionShape* shape, double mass, const btVector3& origin, double restitution) {
    btVector3 inertia(0, 0, 0);
    if (mass > 0) shape->calculateLocalInertia(btScalar(mass), inertia);
    btTransform transform;
    transform.setIdentity();
    transform.setOrigin(origin);
    w.motionStates.push_back(std::make_unique<btDefaultMotionState>(transform));
    btRigidBody::btRigidBodyConstructionInfo info(btScalar(mass), w.motionStates.back().get(), shape, inertia);
    info.m_friction = 0;
    info.m_rollingFriction = 0;
    info.m_spinningFriction = 0;
    info.m_restitution = btScalar(restitution);
    info.m_linearDamping = 0;
    info.m_angularDamping = 0;
    w.bodies.push_back(std::make_unique<btRigidBody>(info));
    btRigidBody* body = w.bodies.back().get();
    body->setFriction(0);
    body->setRollingFriction(0);
    body->setRestitution(btScalar(restitution));
    w.world.addRigidBody(body);
    return body;
}

std::vector<Vec3<double>> positions(const PileWorld& w) {
    std::vector<Vec3<double>> x(w.balls.size());
    for (size_t i = 0; i < w.balls.size(); ++i) {
        const btVector3& p = w.balls[i]->getCenterOfMassPosition();
        x[i] = {double(p.x()), double(p.y()), double(p.z())};
    }
    return x;
}

PileEnergySample energy(const PileWorld& w, double time, double gravity) {
    PileEnergySample s;
    s.time = time;
    for (const btRigidBody* b : w.balls) {
        const double m = 1.0 / double(b->getInvMass());
        const btVector3& v = b->getLinearVelocity();
        const btVector3& omega = b->getAngularVelocity();
        const btVector3 inertia = b->getLocalInertia();
        s.kinetic += 0.5 * m * double(v.length2()) +
                     0.5 * double(inertia.x() * omega.x() * omega.x() + inertia.y() * omega.y() * omega.y() +
                                  inertia.z() * omega.z() * omega.z());
        s.potential += m * gravity * double(b->getCenterOfMassPosition().z());
    }
    return s;
}

int run(const DriverOptions& o) {
    const ParticleState initial = readStateCsv(o.statePath);
    PileWorld w;
    w.world.setGravity(btVector3(0, 0, btScalar(-o.gravity)));
    w.world.setInternalTickCallback(countTick, &w);
    const double bodyRestitution = std::sqrt(o.restitution);
    const double wallRestitution = o.wallRestitution / bodyRestitution;  // product with a ball's: e_w
    // Walls: n.x = c with n pointing into the box.
    for (int a = 0; a < 3; ++a) {
        for (int side = 0; side < 2; ++side) {
            btVector3 normal(0, 0, 0);
            normal[a] = side == 0 ? 1 : -1;
            const double constant = side == 0 ? 0.0 : -o.box[size_t(a)];
            w.planeShapes.push_back(std::make_unique<btStaticPlaneShape>(normal, btScalar(constant)));
            addBody(w, w.planeShapes.back().get(), 0.0, btVector3(0, 0, 0), wallRestitution);
        }
    }
    w.sphere = std::make_unique<btSphereShape>(btScalar(o.radius));
    w.balls.reserve(initial.size());
    for (size_t i = 0; i < initial.size(); ++i) {
        const Vec3<double>& p = initial.position[i];
        btRigidBody* ball =
            addBody(w, w.sphere.get(), o.mass, btVector3(btScalar(p.x), btScalar(p.y), btScalar(p.z)), bodyRestitution);
        const Vec3<double>& v = initial.velocity[i];
        ball->setLinearVelocity(btVector3(btScalar(v.x), btScalar(v.y), btScalar(v.z)));
        ball->setActivationState(DISABLE_DEACTIVATION);
        w.balls.push_back(ball);
    }

    const double frame = 1.0 / 60.0;
    const double fixedStep = frame / o.substeps;
    const int64_t frames = std::llround(o.seconds / frame);
    std::vector<PileEnergySample> samples{energy(w, 0.0, o.gravity)};
    PileFrameTimes times;
    using Clock = std::chrono::steady_clock;
    Clock::time_point lastProgress = Clock::now();
    for (int64_t f = 0; f < frames; ++f) {
        const Clock::time_point start = Clock::now();
        w.world.stepSimulation(btScalar(frame), o.substeps, btScalar(fixedStep));
        times.ms.push_back(1e3 * std::chrono::duration<double>(Clock::now() - start).count());
        samples.push_back(energy(w, double(w.ticks) * fixedStep, o.gravity));
        if (std::chrono::duration<double>(Clock::now() - lastProgress).count() > 2.0) {
            lastProgress = Clock::now();
            std::fprintf(stderr, "[bullet] N = %zu: t = %.2f s, %.1f ms/frame\n", w.balls.size(), samples.back().time,
                         times.meanOfLast(60));
        }
    }

    const std::array<double, 3> box{o.box[0], o.box[1], o.box[2]};
    const PileStateMeasures measures = measurePileState(positions(w), o.radius, box);
    const std::optional<double> rest = pileTimeToRest(samples);
    const PileEnergySample& first = samples.front();
    const PileEnergySample& last = samples.back();
    const btContactSolverInfo& solverInfo = w.world.getSolverInfo();
    nlohmann::json out;
    out["engine"] = "bullet";
    out["bullet_version"] = btGetVersion();
    out["precision"] = sizeof(btScalar) == 8 ? "fp64" : "fp32";
    out["n"] = w.balls.size();
    out["frames"] = frames;
    out["substeps"] = o.substeps;
    out["fixed_steps"] = w.ticks;
    out["simulated_seconds"] = last.time;
    out["ms_per_frame_mean"] = times.mean();
    out["ms_per_frame_last_second"] = times.meanOfLast(60);
    out["ms_per_frame"] = times.ms;  // so that a shorter run can be compared over the frames it completed
    out["max_overlap_fraction"] = measures.maxOverlap;
    out["max_wall_penetration_fraction"] = measures.maxWallPenetration;
    out["outside"] = measures.outside;
    out["non_finite"] = measures.nonFinite;
    out["energy_start"] = first.kinetic + first.potential;
    out["energy_end"] = last.kinetic + last.potential;
    out["kinetic_end"] = last.kinetic;
    out["potential_released"] = first.potential - last.potential;
    out["time_to_rest"] = rest ? nlohmann::json(*rest) : nlohmann::json(nullptr);
    out["solver_iterations"] = solverInfo.m_numIterations;
    out["split_impulse"] = solverInfo.m_splitImpulse != 0;
    out["restitution_velocity_threshold"] = solverInfo.m_restitutionVelocityThreshold;
    out["body_restitution"] = bodyRestitution;
    out["wall_body_restitution"] = wallRestitution;
    out["sleeping"] = false;
    std::cout << out.dump() << std::endl;
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    DriverOptions o;
    CLI::App app{"The ball pile of `corebox bench pile` in Bullet; prints one JSON object"};
    app.add_option("--state", o.statePath, "Initial state CSV (id,species,x,y,z,vx,vy,vz)")->required();
    app.add_option("--box", o.box, "Box edges Lx,Ly,Lz (z up)")->delimiter(',')->expected(3)->capture_default_str();
    app.add_option("--radius", o.radius, "Ball radius")->capture_default_str();
    app.add_option("--mass", o.mass, "Ball mass")->capture_default_str();
    app.add_option("--gravity", o.gravity, "Gravity along -z")->capture_default_str();
    app.add_option("--restitution", o.restitution, "Ball-ball restitution (each body gets its square root)")
        ->capture_default_str();
    app.add_option("--wall-restitution", o.wallRestitution, "Ball-wall restitution")->capture_default_str();
    app.add_option("--seconds", o.seconds, "Simulated time")->capture_default_str();
    app.add_option("--substeps", o.substeps, "Fixed steps per 1/60 s frame")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    CLI11_PARSE(app, argc, argv);
    try {
        return run(o);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "corebox_bullet_pile: %s\n", e.what());
        return 2;
    }
}
