#include "thermostat.h"

#include <algorithm>
#include <cmath>

#include "rng.h"
#include "thermostat_formulas.h"

namespace corebox {
namespace {

// A stream of normals and uniforms for one step's thermostat decision: draw k uses Philox block
// (seed, id = k, counter = step).
struct StepStream {
    uint64_t seed;
    int64_t step;
    uint32_t* index;

    Philox4 next() { return drawBlock(seed, (*index)++, uint64_t(step), RngPurpose::Thermostat); }
    double gaussian() {
        double g0, g1;
        gaussianPair(next(), &g0, &g1);
        return g0;
    }
    double uniform() {
        const Philox4 r = next();
        return uniformOpen(r.v[0], r.v[1]);
    }
};

double gammaDraw(double shape, StepStream& stream) {
    if (shape < 1.0) {
        // Gamma(a) = Gamma(a + 1) U^(1/a)
        const double u = stream.uniform();
        return gammaDraw(shape + 1.0, stream) * std::pow(u, 1.0 / shape);
    }
    const double d = shape - 1.0 / 3.0;
    const double c = 1.0 / std::sqrt(9.0 * d);
    for (;;) {
        const double x = stream.gaussian();
        const double v0 = 1.0 + c * x;
        if (v0 <= 0) continue;
        const double v = v0 * v0 * v0;
        const double u = stream.uniform();
        if (std::log(u) < 0.5 * x * x + d - d * v + d * std::log(v)) return d * v;
    }
}

}  // namespace

double chiSquaredDraw(double k, uint64_t seed, int64_t step, uint32_t* drawIndex) {
    if (k <= 0) return 0;
    StepStream stream{seed, step, drawIndex};
    return 2.0 * gammaDraw(0.5 * k, stream);
}

ThermostatResult applyThermostat(Backend& backend, const ThermostatDef& def, double dt, int64_t step, uint64_t seed,
                                 int64_t degreesOfFreedom) {
    ThermostatResult result;
    if (def.kind == ThermostatKind::None || degreesOfFreedom <= 0) return result;
    const double kinetic = backend.kineticEnergy();
    result.kineticBefore = result.kineticAfter = kinetic;
    if (kinetic <= 0) return result;  // nothing to scale (all at rest)
    const double nf = double(degreesOfFreedom);
    const double target = 0.5 * nf * def.temperature;
    double next = kinetic;
    if (def.kind == ThermostatKind::Bussi) {
        uint32_t index = 0;
        StepStream stream{seed, step, &index};
        const double r1 = stream.gaussian();
        const double s = chiSquaredDraw(nf - 1.0, seed, step, &index);
        next = bussiKineticEnergy(kinetic, target, nf, std::exp(-dt / def.tau), r1, s);
    } else {
        next = rescaleKineticEnergy(kinetic, target, dt, def.tau);
    }
    next = std::max(next, 0.0);
    backend.scaleVelocities(std::sqrt(next / kinetic));
    result.kineticAfter = next;
    return result;
}

}  // namespace corebox
