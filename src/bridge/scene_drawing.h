// How a scene is drawn (the bridge from simulation to renderer; only the app and the benchmarks see
// both): the render style of a scene (palette, legend, speed range), and instances made from a host
// state with the backends' own formula (particleInstanceOf) for tests and tools that hold a state
// rather than a running backend.
#pragma once

#include <vector>

#include "particle_state.h"
#include "render_style.h"
#include "scene.h"

namespace corebox {

// Colour key: species index, or the speed |v| in speed mode.
void buildInstances(const ParticleState& state, const Scene& scene, ColorMode mode, std::vector<ParticleInstance>& out);

// speedMax <= 0 picks 3.5 sqrt(kT / m_lightest) at the larger of the initial and target
// temperatures: above the 99.9th percentile of Maxwell-Boltzmann, fixed for the whole run so
// colours compare across frames.
RenderStyle renderStyleFor(const Scene& scene, ColorMode mode, double speedMax = 0.0);

}  // namespace corebox
