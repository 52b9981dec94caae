// Scenes built in code for the physics tests, and the backend parameter they run under. Every
// physics test body that steps a simulation is a value-parameterized test (TEST_P) over the backend
// names "cpu" and "cuda" (DESIGN.md sec. 5), instantiated in its file as
//     INSTANTIATE_TEST_SUITE_P(Backends, Suite, ::testing::ValuesIn(backendNames()), backendInstanceName);
// which names the instances Backends/Suite.Test/cpu and Backends/Suite.Test/cuda. Backends come from
// the factory, as in the app. An instance whose backend this build or machine lacks skips with the
// reason (ctest lists it as skipped), so a missing GPU never passes silently.
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "backend_factory.h"
#include "initial_conditions.h"
#include "scene.h"
#include "simulation.h"

namespace corebox::testing {

// ---- the backend parameter ----

inline std::vector<std::string> backendNames() { return {"cpu", "cuda"}; }

inline std::string backendInstanceName(const ::testing::TestParamInfo<std::string>& info) { return info.param; }

// Why the named backend cannot run here, or "" when it can.
inline std::string backendMissing(const std::string& backend) {
    if (backend != "cuda") return "";
#if COREBOX_WITH_CUDA
    return cudaAvailable() ? "" : "no CUDA device: the cuda instance of this test is skipped";
#else
    return "built without CUDA (no nvcc or COREBOX_CUDA=OFF): the cuda instance of this test is skipped";
#endif
}

// Base of the backend-parameterized suites: GetParam() is the backend name.
class OnEveryBackend : public ::testing::TestWithParam<std::string> {
protected:
    void SetUp() override {
        const std::string missing = backendMissing(GetParam());
        if (!missing.empty()) GTEST_SKIP() << missing;
    }
    const std::string& backendName() const { return GetParam(); }
};

// threads: CPU threads (0: all cores); a GPU backend ignores it. Checks that the factory gave the
// backend asked for, so that an instance never runs on another backend than its name says.
inline std::unique_ptr<Backend> makeTestBackend(const std::string& backend, Precision precision, int threads = 0) {
    std::unique_ptr<Backend> made = makeBackend(BackendChoice{backend, precision, threads, 0});
    if (made->name() != backend)
        throw std::logic_error("asked the factory for '" + backend + "', got '" + made->name() + "'");
    return made;
}

// ---- scenes and states ----

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

inline std::unique_ptr<Simulation> makeSimulation(const std::string& backend, const Scene& scene,
                                                  const ParticleState& state, int threads = 0,
                                                  SimulationLimits limits = SimulationLimits{}) {
    return std::make_unique<Simulation>(scene, makeTestBackend(backend, scene.integrator.precision, threads), state,
                                        limits);
}

inline std::unique_ptr<Simulation> makeSimulation(const std::string& backend, const Scene& scene, int threads = 0) {
    return makeSimulation(backend, scene, makeInitialState(scene), threads);
}

}  // namespace corebox::testing
