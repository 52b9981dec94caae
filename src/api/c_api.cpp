// corebox_c.h over corebox::World: each call runs inside one guard that turns the C++ exceptions into
// status codes and keeps the message for corebox_last_error().
#include "corebox/corebox_c.h"

#include <new>
#include <string>
#include <vector>

#include "corebox/corebox.h"

using namespace corebox;

struct corebox_world {
    World world;
    std::vector<corebox_contact> contacts;  // the last call's contacts in C layout
};

namespace {

thread_local std::string t_lastError;

template <class Fn>
corebox_status guarded(Fn&& fn) {
    try {
        return fn();
    } catch (const InputError& e) {
        t_lastError = e.what();
        return COREBOX_INPUT_ERROR;
    } catch (const InstabilityError& e) {
        t_lastError = e.what();
        return COREBOX_INSTABILITY;
    } catch (const DeviceError& e) {
        t_lastError = e.what();
        return COREBOX_DEVICE_ERROR;
    } catch (const std::bad_alloc&) {
        t_lastError = "out of memory";
        return COREBOX_ERROR;
    } catch (const std::exception& e) {
        t_lastError = e.what();
        return COREBOX_ERROR;
    }
}

corebox_status missing(const char* what) {
    t_lastError = std::string(what) + " is NULL";
    return COREBOX_INPUT_ERROR;
}

Vec3d vec(const double v[3]) { return Vec3d{v[0], v[1], v[2]}; }

void put(const Vec3d& v, double out[3]) {
    out[0] = v.x;
    out[1] = v.y;
    out[2] = v.z;
}

ParticleSpecies speciesOf(const corebox_species& s) {
    ParticleSpecies p;
    p.name = s.name ? s.name : "";
    p.mass = s.mass;
    p.radius = s.radius;
    p.epsilon = s.epsilon;
    p.sigma = s.sigma;
    p.acceleration = vec(s.acceleration);
    p.color = {s.color[0], s.color[1], s.color[2]};
    return p;
}

BackendKind backendOf(corebox_backend b) {
    switch (b) {
    case COREBOX_BACKEND_CPU: return BackendKind::Cpu;
    case COREBOX_BACKEND_CUDA: return BackendKind::Cuda;
    case COREBOX_BACKEND_AUTO: return BackendKind::Auto;
    }
    throw InputError("backend: " + std::to_string(int(b)) + " is not a corebox_backend");
}

void putInfo(const StepInfo& s, corebox_step_info* info) {
    if (!info) return;
    info->substeps = s.substeps;
    info->simulated_time = s.simulatedTime;
    info->dropped_time = s.droppedTime;
    info->alpha = s.alpha;
    info->pair_collisions = s.pairCollisions;
    info->wall_collisions = s.wallCollisions;
    info->dissipated = s.dissipated;
    info->seconds = s.seconds;
    info->seconds_impacts = s.secondsImpacts;
    info->seconds_contacts = s.secondsContacts;
    info->seconds_listings = s.secondsListings;
    info->contact_listings = s.contactListings;
    info->overlap_left = s.overlapLeft;
}

void keepContacts(corebox_world* w) {
    w->contacts.clear();
    for (const Contact& c : w->world.contacts()) {
        corebox_contact out{};
        out.is_wall = c.kind == ContactKind::Wall;
        out.a = c.a;
        out.b = c.b;
        out.wall_axis = c.wallAxis;
        out.wall_side = c.wallSide;
        out.time = c.time;
        put(c.normal, out.normal);
        out.impulse = c.impulse;
        out.speed = c.speed;
        w->contacts.push_back(out);
    }
}

corebox_status placed(const PlacementResult& p) {
    if (p.placed) return COREBOX_OK;
    t_lastError = p.reason;
    return COREBOX_REJECTED;
}

}  // namespace

extern "C" {

const char* corebox_version(void) { return version(); }

const char* corebox_last_error(void) { return t_lastError.c_str(); }

void corebox_world_def_default(corebox_world_def* def) {
    if (!def) return;
    const WorldDef d;
    const ParticleSpecies& s = d.species.front();
    *def = corebox_world_def{};
    put(d.boxSize, def->box_size);
    def->wall_restitution = d.wallRestitution;
    def->restitution = d.restitution;
    put(d.gravity, def->gravity);
    static const std::string defaultName = s.name;  // outlives every def filled here
    def->species0.name = defaultName.c_str();
    def->species0.mass = s.mass;
    def->species0.radius = s.radius;
    def->species0.epsilon = s.epsilon;
    def->species0.sigma = s.sigma;
    put(s.acceleration, def->species0.acceleration);
    for (int k = 0; k < 3; ++k) def->species0.color[k] = s.color[size_t(k)];
    def->substep = d.substep;
    def->max_substeps = d.maxSubsteps;
    def->backend = COREBOX_BACKEND_CPU;
    def->precision = COREBOX_FP64;
    def->threads = d.threads;
    def->gpus = d.gpus;
    def->device = d.device;
    def->contact_sweeps = d.contactSweeps;
    def->impact_rounds = d.impactRounds;
    def->contact_listings = d.contactListings;
}

corebox_status corebox_world_create(const corebox_world_def* def, corebox_world** world) {
    if (!def) return missing("def");
    if (!world) return missing("world");
    return guarded([&] {
        WorldDef d;
        d.boxSize = vec(def->box_size);
        d.wallRestitution = def->wall_restitution;
        d.restitution = def->restitution;
        d.gravity = vec(def->gravity);
        d.species = {speciesOf(def->species0)};
        d.substep = def->substep;
        d.maxSubsteps = def->max_substeps;
        d.backend = backendOf(def->backend);
        d.precision = def->precision == COREBOX_FP32 ? Precision::Fp32 : Precision::Fp64;
        d.threads = def->threads;
        d.gpus = def->gpus;
        d.device = def->device;
        d.contactSweeps = def->contact_sweeps;
        d.impactRounds = def->impact_rounds;
        d.contactListings = def->contact_listings;
        *world = new corebox_world{World(d), {}};
        return COREBOX_OK;
    });
}

corebox_status corebox_world_create_from_scene(const char* path, corebox_backend backend, corebox_world** world) {
    if (!path) return missing("path");
    if (!world) return missing("world");
    return guarded([&] {
        WorldDef d;
        d.backend = backendOf(backend);
        *world = new corebox_world{World::fromSceneFile(path, d), {}};
        return COREBOX_OK;
    });
}

void corebox_world_destroy(corebox_world* world) { delete world; }

corebox_status corebox_world_add_species(corebox_world* world, const corebox_species* species, int* index) {
    if (!world) return missing("world");
    if (!species) return missing("species");
    return guarded([&] {
        const int added = world->world.addSpecies(speciesOf(*species));
        if (index) *index = added;
        return COREBOX_OK;
    });
}

corebox_status corebox_world_add_particle(corebox_world* world, int species, const double position[3], const double velocity[3],
                                          uint64_t* id) {
    if (!world) return missing("world");
    if (!position) return missing("position");
    return guarded([&] {
        const double still[3] = {0, 0, 0};
        const PlacementResult p = world->world.addParticle(ParticleDef{species, vec(position), vec(velocity ? velocity : still)});
        if (id) *id = p.id;
        return placed(p);
    });
}

corebox_status corebox_world_remove_particle(corebox_world* world, uint64_t id) {
    if (!world) return missing("world");
    return guarded([&] {
        world->world.removeParticle(id);
        return COREBOX_OK;
    });
}

corebox_status corebox_world_apply_impulse(corebox_world* world, uint64_t id, const double impulse[3]) {
    if (!world) return missing("world");
    if (!impulse) return missing("impulse");
    return guarded([&] {
        world->world.applyImpulse(id, vec(impulse));
        return COREBOX_OK;
    });
}

corebox_status corebox_world_set_velocity(corebox_world* world, uint64_t id, const double velocity[3]) {
    if (!world) return missing("world");
    if (!velocity) return missing("velocity");
    return guarded([&] {
        world->world.setVelocity(id, vec(velocity));
        return COREBOX_OK;
    });
}

corebox_status corebox_world_set_position(corebox_world* world, uint64_t id, const double position[3]) {
    if (!world) return missing("world");
    if (!position) return missing("position");
    return guarded([&] { return placed(world->world.setPosition(id, vec(position))); });
}

corebox_status corebox_world_set_gravity(corebox_world* world, const double gravity[3]) {
    if (!world) return missing("world");
    if (!gravity) return missing("gravity");
    return guarded([&] {
        world->world.setGravity(vec(gravity));
        return COREBOX_OK;
    });
}

corebox_status corebox_world_set_restitution(corebox_world* world, double ballBall, double wall) {
    if (!world) return missing("world");
    return guarded([&] {
        world->world.setRestitution(ballBall, wall);
        return COREBOX_OK;
    });
}

corebox_status corebox_world_step(corebox_world* world, double dt, corebox_step_info* info) {
    if (!world) return missing("world");
    return guarded([&] {
        putInfo(world->world.step(dt), info);
        keepContacts(world);
        return COREBOX_OK;
    });
}

corebox_status corebox_world_advance(corebox_world* world, double frameTime, corebox_step_info* info) {
    if (!world) return missing("world");
    return guarded([&] {
        putInfo(world->world.advance(frameTime), info);
        keepContacts(world);
        return COREBOX_OK;
    });
}

size_t corebox_world_particle_count(const corebox_world* world) { return world ? world->world.particleCount() : 0; }

corebox_status corebox_world_positions(corebox_world* world, const double** xyz, size_t* count) {
    if (!world) return missing("world");
    if (!xyz || !count) return missing("xyz or count");
    return guarded([&] {
        const Span<Vec3d> x = world->world.positions();
        static_assert(sizeof(Vec3d) == 3 * sizeof(double), "Vec3d is three packed doubles");
        *xyz = reinterpret_cast<const double*>(x.data);
        *count = x.size;
        return COREBOX_OK;
    });
}

corebox_status corebox_world_velocities(corebox_world* world, const double** xyz, size_t* count) {
    if (!world) return missing("world");
    if (!xyz || !count) return missing("xyz or count");
    return guarded([&] {
        const Span<Vec3d> v = world->world.velocities();
        *xyz = reinterpret_cast<const double*>(v.data);
        *count = v.size;
        return COREBOX_OK;
    });
}

corebox_status corebox_world_ids(corebox_world* world, const uint64_t** ids, size_t* count) {
    if (!world) return missing("world");
    if (!ids || !count) return missing("ids or count");
    const Span<ParticleId> s = world->world.ids();
    *ids = s.data;
    *count = s.size;
    return COREBOX_OK;
}

corebox_status corebox_world_contacts(corebox_world* world, const corebox_contact** contacts, size_t* count) {
    if (!world) return missing("world");
    if (!contacts || !count) return missing("contacts or count");
    *contacts = world->contacts.data();
    *count = world->contacts.size();
    return COREBOX_OK;
}

corebox_status corebox_world_query_radius(corebox_world* world, const double centre[3], double radius, uint64_t* ids, size_t capacity,
                                          size_t* found) {
    if (!world) return missing("world");
    if (!centre) return missing("centre");
    if (!ids && capacity > 0) return missing("ids");
    return guarded([&] {
        const std::vector<ParticleId> hits = world->world.queryRadius(vec(centre), radius);
        for (size_t k = 0; k < hits.size() && k < capacity; ++k) ids[k] = hits[k];
        if (found) *found = hits.size();
        return COREBOX_OK;
    });
}

corebox_status corebox_world_energy(corebox_world* world, corebox_energy* energy) {
    if (!world) return missing("world");
    if (!energy) return missing("energy");
    return guarded([&] {
        const EnergyBalance e = world->world.energy();
        energy->kinetic = e.kinetic;
        energy->potential = e.potential;
        energy->dissipated = e.dissipated;
        energy->external = e.external;
        energy->conserved = e.conserved();
        put(e.momentum, energy->momentum);
        return COREBOX_OK;
    });
}

corebox_status corebox_world_state_hash(corebox_world* world, uint64_t* hash) {
    if (!world) return missing("world");
    if (!hash) return missing("hash");
    return guarded([&] {
        *hash = world->world.stateHash();
        return COREBOX_OK;
    });
}

}  // extern "C"
