// Scenes the benchmarks measure, shared so the force pass and the full steps describe one model.
#pragma once

#include <cmath>
#include <cstdint>

#include "scene.h"

namespace corebox {

// LJ particles at number density `density` whose hard cores (radius 0.56: contact at 1.12 sigma,
// near the bottom of the well) collide often at T = 1.5: the report's model of potentials plus
// hard-core collisions.
inline Scene throughputScene(int64_t n, double density, Precision precision, Method method) {
    Scene scene;
    SpeciesDef s;
    s.name = "LJ";
    s.count = n;
    s.radius = 0.56;
    scene.species = {s};
    const double box = std::cbrt(double(n) / density);
    scene.box.size = {box, box, box};
    scene.integrator.method = method;
    scene.integrator.dt = 1e-3;
    scene.integrator.precision = precision;
    scene.thermostat.kind = ThermostatKind::None;
    scene.init.temperature = 1.5;
    return scene;
}

}  // namespace corebox
