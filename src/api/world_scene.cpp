#include "world_scene.h"

#include "scene_validation.h"
#include "vocabulary.h"

namespace corebox {

SpeciesDef speciesDefOf(const ParticleSpecies& p) {
    SpeciesDef s;
    s.name = p.name;
    s.count = 0;
    s.mass = p.mass;
    s.radius = p.radius;
    s.sigma = p.sigma;
    s.epsilon = p.epsilon;
    s.color = p.color;
    s.acceleration = {p.acceleration.x, p.acceleration.y, p.acceleration.z};
    return s;
}

ParticleSpecies particleSpeciesOf(const SpeciesDef& s) {
    ParticleSpecies p;
    p.name = s.name;
    p.mass = s.mass;
    p.radius = s.radius;
    p.sigma = s.sigma;
    p.epsilon = s.epsilon;
    p.color = s.color;
    p.acceleration = Vec3d{s.acceleration[0], s.acceleration[1], s.acceleration[2]};
    return p;
}

Scene sceneOfWorldDef(const WorldDef& def) {
    Scene scene;
    scene.sourcePath = "WorldDef";
    scene.box.size = {def.boxSize.x, def.boxSize.y, def.boxSize.z};
    scene.box.wallRestitution = def.wallRestitution;
    for (const ParticleSpecies& p : def.species) scene.species.push_back(speciesDefOf(p));
    scene.interaction.restitution = def.restitution;
    scene.interaction.gravity = {def.gravity.x, def.gravity.y, def.gravity.z};
    scene.interaction.cutoff = def.cutoff;
    if (!(def.contactSweeps >= 0)) throw InputError("WorldDef: contactSweeps: must be >= 0 (0: corebox's own cap, 16)");
    scene.interaction.contactSweeps = def.contactSweeps;
    const int roundsLimit = InteractionDef::kMaxCollisionRoundsLimit;
    if (!(def.impactRounds >= 0 && def.impactRounds <= roundsLimit))
        throw InputError("WorldDef: impactRounds: must be 0 to " + std::to_string(roundsLimit) +
                         " (0: corebox's own cap, 64)");
    if (def.impactRounds > 0) scene.interaction.maxCollisionRounds = def.impactRounds;
    static_assert(WorldDef::kMaxContactListings == InteractionDef::kMaxContactListings, "one limit, said twice");
    const int listingsLimit = InteractionDef::kMaxContactListings;
    if (!(def.contactListings >= 0 && def.contactListings <= listingsLimit))
        throw InputError("WorldDef: contactListings: must be 0 to " + std::to_string(listingsLimit) +
                         " (0: corebox's own cap, " + std::to_string(listingsLimit) + ")");
    scene.interaction.contactListings = def.contactListings;
    if (!parseMethod(def.method, &scene.integrator.method)) throw InputError("WorldDef: method: " + methodTable().unknown(def.method));
    scene.integrator.dt = def.substep;
    scene.integrator.precision = def.precision;
    // A game world exchanges no heat: no thermostat, and particles start with the velocities given.
    scene.thermostat.kind = ThermostatKind::None;
    scene.init.temperature = 0;
    scene.devices.gpus = def.gpus;
    scene.devices.exchange = def.exchange;
    if (!(def.maxSubsteps >= 1)) throw InputError("WorldDef: maxSubsteps: must be >= 1, not " + std::to_string(def.maxSubsteps));
    if (!(def.threads >= 0)) throw InputError("WorldDef: threads: must be >= 0 (0: every hardware thread)");
    if (!(def.gpus >= 0)) throw InputError("WorldDef: gpus: must be >= 0 (0: the measured best for the count)");
    validateWorldScene(scene);
    return scene;
}

void validateWorldScene(const Scene& scene) {
    // A world may be empty, a scene file may not: the rules on counts and packing are the World's to
    // apply per placement, so the scene is checked as if it held one particle.
    Scene checked = scene;
    for (SpeciesDef& s : checked.species) s.count = 0;
    if (!checked.species.empty()) checked.species.front().count = 1;
    validateScene(checked, SceneLocations(scene.sourcePath.empty() ? "WorldDef" : scene.sourcePath));
}

BackendChoice backendChoiceOf(const WorldDef& def, const Scene& scene) {
    BackendChoice choice;
    choice.name = def.backend == BackendKind::Cpu ? "cpu" : (def.backend == BackendKind::Cuda ? "cuda" : "auto");
    choice.threads = def.threads;
    choice.device = def.device;
    return backendChoiceFor(scene, choice);
}

}  // namespace corebox
