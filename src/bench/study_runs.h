// What the study (study.h) and the automatic integrator choice (auto_integrator.h) share: a scene
// with another integrator, a simulation of it on a named backend, stepping to a time, and a slope.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "particle_state.h"
#include "scene.h"
#include "simulation.h"

namespace corebox {

// `base` run with another method, precision and step; tolerance > 0: adaptive (dp5).
Scene sceneWithIntegrator(const Scene& base, Method method, Precision precision, double dt, double tolerance = 0);

// A simulation of `scene` from `initial` on `backend` ("auto", "cpu", "cuda") with `threads`.
std::unique_ptr<Simulation> simulationOn(const Scene& scene, const ParticleState& initial, const std::string& backend, int threads,
                                         SimulationLimits limits = SimulationLimits{});

// Steps to time t: fixed steps land there when they divide it; an adaptive step is cut short so that
// the last one ends on t.
void advanceTo(Simulation& sim, double t);

// Least-squares slope of y over t (0 with fewer than two points).
double leastSquaresSlope(const std::vector<double>& t, const std::vector<double>& y);

}  // namespace corebox
