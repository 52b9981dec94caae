// Scenes built in code for the physics tests: small, explicit, and run on the CPU backend.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "cpu_backend.h"
#include "initial_conditions.h"
#include "scene.h"
#include "simulation.h"

namespace corebox::testing {

// One species of hard spheres (no pair force) of radius 0.5 in a cubic box, elastic, no thermostat.
inline Scene hardSphereScene(int64_t count, double box, Method method = Method::Verlet, double dt = 1e-3) {
    Scene scene;
    SpeciesDef s;
    s.name = "A";
    s.count = count;
    s.epsilon = 0;
    scene.species = {s};
    scene.box.size = {box, box, box};
    scene.integrator.method = method;
    scene.integrator.dt = dt;
    scene.thermostat.kind = ThermostatKind::None;
    return scene;
}

inline ParticleState stateOf(const std::vector<Vec3<double>>& x, const std::vector<Vec3<double>>& v,
                             const std::vector<int32_t>& species = {}) {
    ParticleState s;
    s.position = x;
    s.velocity = v;
    s.species = species.empty() ? std::vector<int32_t>(x.size(), 0) : species;
    return s;
}

inline std::unique_ptr<Simulation> makeSimulation(const Scene& scene, const ParticleState& state, int threads = 0,
                                                  SimulationLimits limits = SimulationLimits{}) {
    return std::make_unique<Simulation>(scene, makeCpuBackend(CpuBackendOptions{scene.integrator.precision, threads}), state, limits);
}

inline std::unique_ptr<Simulation> makeSimulation(const Scene& scene, int threads = 0) {
    return makeSimulation(scene, makeInitialState(scene), threads);
}

}  // namespace corebox::testing
