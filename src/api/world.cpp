// corebox::World's public methods (world.h): argument checks and the mapping between ids and slots;
// the mechanics (mirror, uploads, simulation lifetime, energy bookkeeping) are in world_impl.cpp.
#include <algorithm>
#include <chrono>
#include <cmath>

#include "corebox/corebox.h"
#include "initial_conditions.h"
#include "scene_io.h"
#include "state_hash.h"
#include "world_impl.h"
#include "world_scene.h"

#ifndef COREBOX_VERSION_STRING
#define COREBOX_VERSION_STRING "0.0.0"
#endif

namespace corebox {

namespace {

void requireFinite(const Vec3d& v, const char* what) {
    if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z)) throw InputError(std::string(what) + " must be finite");
}

Vec3<double> vec3Of(const Vec3d& v) { return Vec3<double>{v.x, v.y, v.z}; }

}  // namespace

const char* version() { return COREBOX_VERSION_STRING; }

World::World(const WorldDef& def) : m_impl(std::make_unique<Impl>(def, sceneOfWorldDef(def))) {}

World::World(std::unique_ptr<Impl> impl) : m_impl(std::move(impl)) {}

World World::fromSceneFile(const std::string& path, const WorldDef& def) {
    Scene scene = loadScene(path);
    if (scene.integrator.automatic)
        throw InputError(path + ": integrator: method = \"auto\" is for `corebox run`; name a method for a World");
    WorldDef used = def;
    used.substep = scene.integrator.dt;
    used.precision = scene.integrator.precision;
    used.gpus = scene.devices.gpus;
    used.exchange = scene.devices.exchange;
    const ParticleState initial = makeInitialState(scene);
    auto impl = std::make_unique<Impl>(used, scene);
    for (size_t i = 0; i < initial.size(); ++i) {
        const Vec3<double>& x = initial.position[i];
        const Vec3<double>& v = initial.velocity[i];
        impl->appendSlot(impl->nextId++, ParticleDef{initial.species[i], Vec3d{x.x, x.y, x.z}, Vec3d{v.x, v.y, v.z}});
    }
    return World(std::move(impl));
}

World::~World() = default;
World::World(World&&) noexcept = default;
World& World::operator=(World&&) noexcept = default;

// ---- species ----

int World::speciesCount() const { return int(m_impl->species.size()); }

const ParticleSpecies& World::species(int index) const {
    if (index < 0 || index >= speciesCount())
        throw InputError("species " + std::to_string(index) + " does not exist (the world has " + std::to_string(speciesCount()) + ")");
    return m_impl->species[size_t(index)];
}

int World::speciesIndex(const std::string& name) const {
    for (size_t s = 0; s < m_impl->species.size(); ++s) {
        if (m_impl->species[s].name == name) return int(s);
    }
    return -1;
}

int World::addSpecies(const ParticleSpecies& added) {
    Scene next = m_impl->scene;
    next.species.push_back(speciesDefOf(added));
    // A scene file's mixing matrix grows by a row and column of 1 (the default coupling).
    std::vector<std::vector<double>>& mixing = next.interaction.mixing;
    if (!mixing.empty()) {
        for (std::vector<double>& row : mixing) row.push_back(1.0);
        mixing.emplace_back(mixing.size() + 1, 1.0);
    }
    validateWorldScene(next);  // names the rule broken; nothing changes when it throws
    m_impl->ensureMirror();    // an edit uploads the whole mirror (flushEdits)
    m_impl->scene = std::move(next);
    m_impl->species.push_back(added);
    if (added.radius > m_impl->maxRadius) {
        m_impl->maxRadius = added.radius;
        m_impl->gridFresh = false;
    }
    m_impl->edited = true;
    return speciesCount() - 1;
}

// ---- particles ----

PlacementResult World::addParticle(const ParticleDef& particle) {
    Impl& w = *m_impl;
    w.ensureMirror();  // the add uploads the whole mirror (flushEdits): one download, not positions and then both
    w.ensureGrid();
    PlacementResult p = w.checkPlacement(particle.species, particle.position, ~uint32_t(0));
    if (!p.placed) return p;
    requireFinite(particle.velocity, "addParticle: velocity");
    p.id = w.nextId++;
    w.appendSlot(p.id, particle);
    return p;
}

std::vector<PlacementResult> World::addParticles(const std::vector<ParticleDef>& particles) {
    std::vector<PlacementResult> out;
    out.reserve(particles.size());
    for (const ParticleDef& p : particles) out.push_back(addParticle(p));
    return out;
}

void World::removeParticle(ParticleId id) {
    Impl& w = *m_impl;
    w.removeSlot(w.slotOf(id));
}

bool World::contains(ParticleId id) const { return m_impl->slots.count(id) > 0; }

size_t World::particleCount() const { return m_impl->ids.size(); }

void World::applyImpulse(ParticleId id, Vec3d impulse) {
    Impl& w = *m_impl;
    const uint32_t slot = w.slotOf(id);
    requireFinite(impulse, "applyImpulse: impulse");
    w.ensureMirror();
    const double m = w.species[size_t(w.speciesIndex[slot])].mass;
    Vec3d& v = w.velocities[slot];
    v = Vec3d{v.x + impulse.x / m, v.y + impulse.y / m, v.z + impulse.z / m};
    w.edited = true;
}

void World::setVelocity(ParticleId id, Vec3d velocity) {
    Impl& w = *m_impl;
    const uint32_t slot = w.slotOf(id);
    requireFinite(velocity, "setVelocity: velocity");
    w.ensureMirror();
    w.velocities[slot] = velocity;
    w.edited = true;
}

PlacementResult World::setPosition(ParticleId id, Vec3d position) {
    Impl& w = *m_impl;
    const uint32_t slot = w.slotOf(id);
    w.ensureMirror();  // the move uploads the whole mirror (flushEdits): one download, not positions and then both
    w.ensureGrid();
    PlacementResult p = w.checkPlacement(w.speciesIndex[slot], position, slot);
    p.id = id;
    if (!p.placed) return p;
    w.positions[slot] = position;
    w.simIndex[slot] = -1;  // its contacts stay behind
    w.gridFresh = false;
    w.edited = true;
    return p;
}

Vec3d World::position(ParticleId id) {
    const uint32_t slot = m_impl->slotOf(id);
    m_impl->ensurePositions();
    return m_impl->positions[slot];
}

Vec3d World::velocity(ParticleId id) {
    const uint32_t slot = m_impl->slotOf(id);
    m_impl->ensureMirror();
    return m_impl->velocities[slot];
}

int World::speciesOf(ParticleId id) const { return m_impl->speciesIndex[m_impl->slotOf(id)]; }

Vec3d World::boxSize() const {
    const std::array<double, 3>& l = m_impl->scene.box.size;
    return Vec3d{l[0], l[1], l[2]};
}

// ---- fields and materials ----

void World::setGravity(Vec3d gravity) {
    requireFinite(gravity, "setGravity: gravity");
    Scene next = m_impl->scene;
    next.interaction.gravity = {gravity.x, gravity.y, gravity.z};
    validateWorldScene(next);
    m_impl->scene = std::move(next);
    m_impl->applyLiveParameters();
}

Vec3d World::gravity() const {
    const std::array<double, 3>& g = m_impl->scene.interaction.gravity;
    return Vec3d{g[0], g[1], g[2]};
}

void World::setSpeciesAcceleration(int index, Vec3d acceleration) {
    species(index);  // throws for an unknown species
    requireFinite(acceleration, "setSpeciesAcceleration: acceleration");
    Scene next = m_impl->scene;
    next.species[size_t(index)].acceleration = {acceleration.x, acceleration.y, acceleration.z};
    validateWorldScene(next);
    m_impl->scene = std::move(next);
    m_impl->species[size_t(index)].acceleration = acceleration;
    m_impl->applyLiveParameters();
}

void World::setRestitution(double ballBall, double wall) {
    Scene next = m_impl->scene;
    next.interaction.restitution = ballBall;
    next.box.wallRestitution = wall;
    validateWorldScene(next);
    m_impl->scene = std::move(next);
    m_impl->applyLiveParameters();
}

// ---- stepping ----

StepInfo World::step() { return step(m_impl->def.substep); }

StepInfo World::step(double dt) {
    const auto start = std::chrono::steady_clock::now();
    m_impl->contacts.clear();
    StepInfo info = m_impl->stepOnce(dt, 0.0, StepInfo{});
    info.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return info;
}

StepInfo World::advance(double frameTime) {
    if (!(frameTime >= 0) || !std::isfinite(frameTime))
        throw InputError("advance: frameTime must be >= 0 and finite, not " + std::to_string(frameTime));
    const auto start = std::chrono::steady_clock::now();
    Impl& w = *m_impl;
    w.contacts.clear();
    const double h = w.def.substep;
    w.accumulator += frameTime;
    StepInfo info;
    while (w.accumulator >= h && info.substeps < w.def.maxSubsteps) {
        info = w.stepOnce(h, info.simulatedTime, info);
        w.accumulator -= h;
    }
    if (w.accumulator >= h) {  // a slow frame: keep the fraction of a substep, drop the rest
        const double keep = std::fmod(w.accumulator, h);
        info.droppedTime = w.accumulator - keep;
        w.accumulator = keep;
    }
    info.alpha = w.accumulator / h;
    info.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return info;
}

double World::time() const { return m_impl->time; }

int64_t World::stepCount() const { return m_impl->steps; }

// ---- reading state ----

Span<ParticleId> World::ids() { return Span<ParticleId>{m_impl->ids.data(), m_impl->ids.size()}; }

Span<Vec3d> World::positions() {
    m_impl->ensurePositions();
    return Span<Vec3d>{m_impl->positions.data(), m_impl->positions.size()};
}

Span<Vec3d> World::velocities() {
    m_impl->ensureMirror();
    return Span<Vec3d>{m_impl->velocities.data(), m_impl->velocities.size()};
}

Span<int32_t> World::speciesIndices() { return Span<int32_t>{m_impl->speciesIndex.data(), m_impl->speciesIndex.size()}; }

DeviceState World::deviceState() {
    m_impl->flushEdits();
    m_impl->bindThread();
    return m_impl->sim ? m_impl->sim->backend().deviceState() : DeviceState{};
}

// ---- contacts and queries ----

const std::vector<Contact>& World::contacts() const { return m_impl->contacts; }

std::vector<ParticleId> World::queryRadius(Vec3d centre, double radius) {
    requireFinite(centre, "queryRadius: centre");
    if (!(radius >= 0) || !std::isfinite(radius)) throw InputError("queryRadius: radius must be >= 0 and finite");
    Impl& w = *m_impl;
    w.ensureGrid();
    std::vector<ParticleId> found;
    const double r2 = radius * radius;
    w.grid.forNear(centre, radius, [&](uint32_t slot) {
        const Vec3d& x = w.positions[slot];
        const double dx = x.x - centre.x, dy = x.y - centre.y, dz = x.z - centre.z;
        if (dx * dx + dy * dy + dz * dz <= r2) found.push_back(w.ids[slot]);
    });
    std::sort(found.begin(), found.end());  // by ascending id; the grid visits each slot once
    return found;
}

// ---- bookkeeping ----

EnergyBalance World::energy() {
    Impl& w = *m_impl;
    w.flushEdits();
    w.bindThread();
    EnergyBalance e;
    if (w.sim) {
        const EnergySums sums = w.sim->backend().energies();
        e.kinetic = sums.kinetic;
        e.potential = sums.potential;
        e.momentum = Vec3d{sums.momentum.x, sums.momentum.y, sums.momentum.z};
    }
    e.dissipated = w.dissipated();
    e.external = w.externalWork();
    return e;
}

uint64_t World::stateHash() {
    Impl& w = *m_impl;
    w.ensureMirror();
    ParticleState state;
    state.resize(w.ids.size());
    for (size_t i = 0; i < w.ids.size(); ++i) {
        state.position[i] = vec3Of(w.positions[i]);
        state.velocity[i] = vec3Of(w.velocities[i]);
        state.species[i] = w.speciesIndex[i];
    }
    uint64_t h = corebox::stateHash(state);
    for (ParticleId id : w.ids) h = (h ^ id) * 1099511628211ull;
    return h;
}

std::string World::backendName() const {
    const Backend* backend = m_impl->sim ? &m_impl->sim->backend() : m_impl->idleBackend.get();
    if (!backend) return m_impl->choice.name;
    return backend->name() + " (" + backend->deviceName() + ")";
}

}  // namespace corebox
