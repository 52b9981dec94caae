// Thermostats applied once per step on the total kinetic energy (DESIGN.md sec. 2): the core
// computes the scale factor from the backend's kinetic energy and asks the backend to scale, so
// CPU and GPU runs draw the same random numbers and make the same decision.
#pragma once

#include <cstdint>

#include "backend.h"
#include "scene.h"

namespace corebox {

struct ThermostatResult {
    double kineticBefore = 0;
    double kineticAfter = 0;
    double energyAdded() const { return kineticAfter - kineticBefore; }
};

// Applies `def` for one step of length dt. degreesOfFreedom = 3N (walls break momentum
// conservation, so no d.o.f. are removed). `step` keys the counter-based draws of bussi.
ThermostatResult applyThermostat(Backend& backend, const ThermostatDef& def, double dt, int64_t step, uint64_t seed,
                                 int64_t degreesOfFreedom);

// Sum of k squared standard normals (chi-squared with k d.o.f.) from counter-based draws keyed on
// (seed, step): 2 Gamma(k/2, 1) by Marsaglia & Tsang (2000).
double chiSquaredDraw(double k, uint64_t seed, int64_t step, uint32_t* drawIndex);

}  // namespace corebox
