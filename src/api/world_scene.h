// The translation between the public definitions (corebox/world.h) and the model's Scene: a WorldDef
// is a scene with no particles, no thermostat and the game defaults; a scene file is read as a scene
// and its species shown as ParticleSpecies. Kept apart from world.cpp so that World's methods deal
// with particles and steps only.
#pragma once

#include "backend_factory.h"
#include "corebox/world.h"
#include "scene.h"

namespace corebox {

// The scene of `def` with no particles; throws InputError naming the field of a definition that
// breaks a rule.
Scene sceneOfWorldDef(const WorldDef& def);
SpeciesDef speciesDefOf(const ParticleSpecies& species);
ParticleSpecies particleSpeciesOf(const SpeciesDef& species);
// Validates `scene` as the world's, naming errors "WorldDef: <key>: ...".
void validateWorldScene(const Scene& scene);
// The backend `def` asks for, for `scene` (its precision and [devices] already applied).
BackendChoice backendChoiceOf(const WorldDef& def, const Scene& scene);

}  // namespace corebox
