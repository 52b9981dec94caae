// A bound Lennard-Jones pair far from the walls, with small hard cores that never touch: a smooth
// nonlinear problem for convergence and stability measurements.
#pragma once

#include <cmath>

#include "physics_fixtures.h"

namespace corebox::testing {

inline Scene ljPairScene(Method method, double dt, double cutoff = 2.5, CutoffShift shift = CutoffShift::Force) {
    Scene scene;
    SpeciesDef s;
    s.name = "A";
    s.count = 2;
    s.radius = 0.1;
    scene.species = {s};
    scene.box.size = {20, 20, 20};
    scene.interaction.cutoff = cutoff;
    scene.interaction.shift = shift;
    scene.integrator.method = method;
    scene.integrator.dt = dt;
    scene.thermostat.kind = ThermostatKind::None;
    return scene;
}

// Pair along x at separation r with relative speed vr along x and a tangential speed vt (y).
inline ParticleState ljPairState(double r, double vr, double vt) {
    return stateOf({{10 - r / 2, 10, 10}, {10 + r / 2, 10, 10}}, {{-vr / 2, -vt / 2, 0}, {vr / 2, vt / 2, 0}});
}

// U''(r_min) of the unshifted LJ pair with sigma = eps = x = 1: small oscillations of the reduced
// mass m/2 have omega = sqrt(2 U'').
inline double ljPairOmega() {
    const double r = std::pow(2.0, 1.0 / 6.0);
    const double curvature = 4.0 * (156.0 / std::pow(r, 14) - 42.0 / std::pow(r, 8));
    return std::sqrt(2.0 * curvature);
}

}  // namespace corebox::testing
