// Initial state of a scene: placement (lattice or random non-overlapping) or a particle CSV, and
// Maxwell-Boltzmann velocities per species mass. Every random draw is counter-based (kernels/rng.h),
// so the same scene and seed give the same state on every backend and thread count.
#pragma once

#include <string>

#include "particle_state.h"
#include "scene.h"

namespace corebox {

// Throws InputError when the particles do not fit (packing.h: the rule scene validation applies), a
// particle file is bad, or particles overlap or lie outside the box.
ParticleState makeInitialState(const Scene& scene);

// Gaussian velocities with variance kT/m per component, centre-of-mass velocity removed.
void assignMaxwellBoltzmannVelocities(const Scene& scene, ParticleState& state);

// Every centre within [a, L - a] on each axis and no pair closer than a_i + a_j. `source` names the
// origin in messages (a file, or "placement").
void checkPlacement(const Scene& scene, const ParticleState& state, const std::string& source);

}  // namespace corebox
