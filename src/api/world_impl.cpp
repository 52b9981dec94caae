#include "world_impl.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>

#include "errors.h"
#include "state_conversions.h"
#include "world_scene.h"

namespace corebox {

namespace {

std::string idText(ParticleId id) { return "particle " + std::to_string(id); }

// The mirror's conversions run on the World's threads (state_conversions.h). Tried and not kept: the
// contact log's two conversions (device records to the core's, then to the World's Contact) chunked,
// then on every core: 0.24 ms a landing step against 0.27 and 0.22 against 0.23 (an H200's host, the
// sandbox at 10^5 balls, two calls; about 25,000 impacts a step above the sandbox's flash threshold),
// most likely bound by the growth of the contacts vector, which initialises each Contact on one thread
// (not measured apart).

}  // namespace

World::Impl::Impl(const WorldDef& definition, Scene worldScene) : def(definition), scene(std::move(worldScene)) {
    // Checked here, where a definition and a scene file's world both pass.
    if (!(def.contactMinImpulse >= 0) || !std::isfinite(def.contactMinImpulse))
        throw InputError("WorldDef: contactMinImpulse: must be >= 0 and finite (0: every impact)");
    for (const SpeciesDef& s : scene.species) {
        species.push_back(particleSpeciesOf(s));
        maxRadius = std::max(maxRadius, s.radius);
    }
    choice = backendChoiceOf(def, scene);
    idleBackend = makeBackend(choice);  // a missing GPU is a DeviceError now, not at the first step
}

void World::Impl::bindThread() {
    if (sim) sim->backend().bindCallingThread();
    else if (idleBackend) idleBackend->bindCallingThread();
}

void World::Impl::ensureMirror() {
    if (positionsFresh && velocitiesFresh) return;
    bindThread();
    sim->readState(stateBuffer);
    const ParticleState& state = stateBuffer;
    conversionLoop(int64_t(state.size()), def.threads, [&](int64_t i) {
        positions[size_t(i)] =
            Vec3d{state.position[size_t(i)].x, state.position[size_t(i)].y, state.position[size_t(i)].z};
        velocities[size_t(i)] =
            Vec3d{state.velocity[size_t(i)].x, state.velocity[size_t(i)].y, state.velocity[size_t(i)].z};
    });
    if (!positionsFresh) gridFresh = false;
    positionsFresh = velocitiesFresh = true;
}

void World::Impl::ensurePositions() {
    if (positionsFresh) return;
    bindThread();
    sim->readPositions([&](size_t first, const Vec3<double>* x, size_t count) {
        Vec3d* out = positions.data() + first;
        conversionLoop(int64_t(count), def.threads, [&](int64_t k) { out[k] = Vec3d{x[k].x, x[k].y, x[k].z}; });
    });
    positionsFresh = true;
    gridFresh = false;
}

void World::Impl::ensureGrid() {
    ensurePositions();
    if (gridFresh) return;
    // Two of the largest radii: an overlap check then reaches one cell around the point.
    grid.build(positions, 2.0 * maxRadius);
    gridFresh = true;
}

uint32_t World::Impl::slotOf(ParticleId id) const {
    const auto it = slots.find(id);
    if (it == slots.end()) throw InputError(idText(id) + " is not in the world (never added, or removed)");
    return it->second;
}

PlacementResult World::Impl::checkPlacement(int s, const Vec3d& x, uint32_t self) const {
    PlacementResult p;
    if (s < 0 || size_t(s) >= species.size()) {
        p.reason = "species " + std::to_string(s) + " does not exist (the world has " + std::to_string(species.size()) + ")";
        return p;
    }
    const double r = species[size_t(s)].radius;
    const double at[3] = {x.x, x.y, x.z};
    const std::array<double, 3>& box = scene.box.size;
    static const char* const axisName[3] = {"x", "y", "z"};
    for (int a = 0; a < 3; ++a) {
        if (!std::isfinite(at[a])) {
            p.reason = std::string("position ") + axisName[a] + " is not finite";
            return p;
        }
        if (at[a] < r || at[a] > box[size_t(a)] - r) {
            p.reason = std::string("the hard core (radius ") + std::to_string(r) + ") would cross a wall: " + axisName[a] + " = " +
                       std::to_string(at[a]) + " is outside [" + std::to_string(r) + ", " + std::to_string(box[size_t(a)] - r) + "]";
            return p;
        }
    }
    ParticleId blocker = kNoParticle;
    grid.forNear(x, r + maxRadius, [&](uint32_t slot) {
        if (slot == self) return;
        const Vec3d& y = positions[slot];
        const double dx = x.x - y.x, dy = x.y - y.y, dz = x.z - y.z;
        const double d = r + species[size_t(speciesIndex[slot])].radius;
        if (dx * dx + dy * dy + dz * dz < d * d) blocker = std::min(blocker, ids[slot]);
    });
    if (blocker != kNoParticle) {
        p.blockedBy = blocker;
        p.reason = "the hard core would overlap " + idText(blocker);
        return p;
    }
    p.placed = true;
    return p;
}

void World::Impl::appendSlot(ParticleId id, const ParticleDef& p) {
    ensureMirror();  // an edit uploads the whole mirror (flushEdits)
    const uint32_t slot = uint32_t(ids.size());
    ids.push_back(id);
    positions.push_back(p.position);
    velocities.push_back(p.velocity);
    speciesIndex.push_back(p.species);
    simIndex.push_back(-1);
    slots[id] = slot;
    if (gridFresh && grid.outgrown(ids.size())) gridFresh = false;  // the next query builds it for them all
    if (gridFresh) grid.insert(slot, p.position);
    edited = true;
}

void World::Impl::removeSlot(uint32_t slot) {
    ensureMirror();  // an edit uploads the whole mirror (flushEdits)
    const uint32_t last = uint32_t(ids.size() - 1);
    slots.erase(ids[slot]);
    if (slot != last) {  // the last slot fills the hole: O(1), and the order depends only on the calls
        ids[slot] = ids[last];
        positions[slot] = positions[last];
        velocities[slot] = velocities[last];
        speciesIndex[slot] = speciesIndex[last];
        simIndex[slot] = simIndex[last];
        slots[ids[slot]] = slot;
    }
    ids.pop_back();
    positions.pop_back();
    velocities.pop_back();
    speciesIndex.pop_back();
    simIndex.pop_back();
    gridFresh = false;
    edited = true;
}

void World::Impl::flushEdits() {
    if (!edited) return;
    edited = false;
    bindThread();
    if (ids.empty()) {
        dropSimulation();
        return;
    }
    ParticleState& state = stateBuffer;
    state.resize(ids.size());
    conversionLoop(int64_t(ids.size()), def.threads, [&](int64_t k) {
        const size_t i = size_t(k);
        state.position[i] = Vec3<double>{positions[i].x, positions[i].y, positions[i].z};
        state.velocity[i] = Vec3<double>{velocities[i].x, velocities[i].y, velocities[i].z};
        state.species[i] = speciesIndex[i];
    });
    if (sim) {
        const ContactCarryOver contacts = carriedImpulses(sim->backend().contactWarmStart(), sim->particleCount());
        sim->replaceParticles(scene.species, state);
        sim->backend().restoreContactWarmStart(contacts);
        markSimulationInSync();
        return;
    }
    Scene first = scene;
    for (SpeciesDef& s : first.species) s.count = 0;
    for (int32_t s : state.species) ++first.species[size_t(s)].count;
    // gpus = 0 picks the device count for the particle count, which is known only now.
    std::unique_ptr<Backend> backend;
    if (idleBackend && def.gpus != 0) backend = std::move(idleBackend);
    else {
        idleBackend.reset();
        backend = makeBackend(backendChoiceOf(def, first));
    }
    sim = std::make_unique<Simulation>(first, std::move(backend), state);
    markSimulationInSync();
    sim->backend().setContactLog(def.recordContacts, def.contactMinImpulse);
    const EnergySums e = sim->backend().energies();
    simulationBase = e.kinetic + e.potential;
}

void World::Impl::markSimulationInSync() {
    simIndex.resize(ids.size());
    for (size_t slot = 0; slot < simIndex.size(); ++slot) simIndex[slot] = int64_t(slot);
}

ContactCarryOver World::Impl::carriedImpulses(const ContactCarryOver& contacts, int64_t simCount) const {
    std::vector<int64_t> slotOfIndex(size_t(std::max<int64_t>(simCount, 0)), -1);
    for (size_t slot = 0; slot < simIndex.size(); ++slot) {
        const int64_t i = simIndex[slot];
        if (i >= 0 && i < simCount) slotOfIndex[size_t(i)] = int64_t(slot);
    }
    auto slotOf = [&](int64_t i) { return i >= 0 && i < simCount ? slotOfIndex[size_t(i)] : int64_t(-1); };
    const bool coloured = contacts.colours.size() == contacts.impulses.size();
    ContactCarryOver carried;
    carried.impulses.reserve(contacts.impulses.size());
    for (size_t k = 0; k < contacts.impulses.size(); ++k) {
        const ContactWarmStart& w = contacts.impulses[k];
        const int64_t a = slotOf(w.i);
        if (a < 0) continue;
        const int64_t b = w.partner < 0 ? w.partner : slotOf(w.partner);  // a wall keeps its code
        if (w.partner >= 0 && b < 0) continue;
        // A pair once, from its lower index (isUsableWarmStart).
        carried.impulses.push_back(w.partner < 0 ? ContactWarmStart{a, b, w.lambda}
                                                 : ContactWarmStart{std::min(a, b), std::max(a, b), w.lambda});
        if (coloured) carried.colours.push_back(contacts.colours[k]);
    }
    return carried;
}

void World::Impl::dropSimulation() {
    if (!sim) return;
    bindThread();
    // Emptying the world takes out the energy the particles had: work of -(E_kin + E_pot).
    const EnergySums e = sim->backend().energies();
    pastExternal = externalWork() - (e.kinetic + e.potential);
    pastDissipated += sim->dissipatedEnergy();
    sim.reset();
}

void World::Impl::applyLiveParameters() {
    if (!sim) return;
    bindThread();
    sim->setStepParameters(stepParametersOf(scene));
}

double World::Impl::externalWork() const {
    return pastExternal + (sim ? simulationBase + sim->parameterWork() + sim->thermostatEnergy() : 0.0);
}

double World::Impl::dissipated() const { return pastDissipated + (sim ? sim->dissipatedEnergy() : 0.0); }

StepInfo World::Impl::stepOnce(double dt, double timeOffset, StepInfo info) {
    if (!(dt > 0) || !std::isfinite(dt)) throw InputError("step: dt must be positive and finite, not " + std::to_string(dt));
    flushEdits();
    bindThread();
    if (dt != scene.integrator.dt) {
        scene.integrator.dt = dt;
        applyLiveParameters();
    }
    if (sim) {
        const StepReport r = sim->step();
        info.pairCollisions += r.pairCollisions;
        info.wallCollisions += r.wallCollisions;
        info.dissipated += r.dissipated;
        if (r.roundCapHit) ++info.roundCapHits;
        info.secondsImpacts += r.secondsImpacts;
        info.secondsContacts += r.secondsContacts;
        info.secondsListings += r.secondsListings;
        info.contactListings += r.contactListings;
        info.overlapLeft = std::max(info.overlapLeft, r.contactOverlap);
        if (def.recordContacts) {
            sim->backend().readContactLog(logBuffer);
            for (const ContactRecord& c : logBuffer) {
                Contact out;
                out.a = ids[size_t(c.a)];
                if (c.b >= 0) {
                    out.kind = ContactKind::Pair;
                    out.b = ids[size_t(c.b)];
                } else {
                    const int code = int(-1 - c.b);
                    out.kind = ContactKind::Wall;
                    out.wallAxis = code / 2;
                    out.wallSide = code % 2;
                }
                out.time = timeOffset + c.time;
                out.normal = Vec3d{c.normal.x, c.normal.y, c.normal.z};
                out.impulse = c.impulse;
                out.speed = c.speed;
                contacts.push_back(out);
            }
        }
        positionsFresh = velocitiesFresh = false;
        gridFresh = false;
    }
    time += dt;
    ++steps;
    ++info.substeps;
    info.simulatedTime += dt;
    return info;
}

}  // namespace corebox
