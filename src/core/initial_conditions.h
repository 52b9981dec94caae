// Initial state of a scene: placement (lattice or random non-overlapping) or a particle CSV, and
// Maxwell-Boltzmann velocities per species mass. Every random draw is counter-based (kernels/rng.h),
// so the same scene and seed give the same state on every backend and thread count.
//
// Set-up of millions of particles takes seconds (random placement is a sequential insertion; 10^7
// particles took 50 s on two cores before the overlap check ran on every core), so it reports
// progress through an optional callback. The results do not depend on the thread count.
#pragma once

#include <cstdint>
#include <functional>
#include <string>

#include "particle_state.h"
#include "scene.h"

namespace corebox {

// Where a long set-up is: `stage` ("lattice placement", "random placement", "velocities", "overlap
// check"), `done` of `total` particles. Called every few ten thousand particles, from one thread.
using SetupProgress = std::function<void(const char* stage, int64_t done, int64_t total)>;

// Throws InputError when the particles do not fit (packing.h: the rule scene validation applies), a
// particle file is bad, or particles overlap or lie outside the box.
ParticleState makeInitialState(const Scene& scene, const SetupProgress& progress = nullptr);

// Gaussian velocities with variance kT/m per component, centre-of-mass velocity removed.
void assignMaxwellBoltzmannVelocities(const Scene& scene, ParticleState& state);

// How deep an overlap (a fraction of the contact distance a_i + a_j) or a wall penetration (of the
// radius) a particle file may hold. A resting pile always carries the contact phase's residual
// overlaps (collision_rounds.h: within 1e-3 of a contact distance when converged, well under 1% of a
// diameter in any settled pile), so its saved state must read back; the first step's contact phase
// removes them. Deeper ones are a mistake in the file and are refused.
inline constexpr double kRestingOverlapAccepted = 0.01;

// Every centre within [a, L - a] on each axis and no pair closer than a_i + a_j, up to
// kRestingOverlapAccepted. `source` names the origin in messages (a file, or "placement").
// The overlap check runs on every hardware thread and reports the overlap of the lowest particle
// index, as a check in file order would.
void checkPlacement(const Scene& scene, const ParticleState& state, const std::string& source,
                    const SetupProgress& progress = nullptr);

}  // namespace corebox
