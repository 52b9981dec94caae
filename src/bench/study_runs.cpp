#include "study_runs.h"

#include <algorithm>
#include <cmath>

#include "backend_factory.h"

namespace corebox {

Scene sceneWithIntegrator(const Scene& base, Method method, Precision precision, double dt, double tolerance) {
    Scene s = base;
    s.integrator.method = method;
    s.integrator.precision = precision;
    s.integrator.dt = dt;
    s.integrator.adaptive = tolerance > 0;
    s.integrator.automatic = false;
    if (tolerance > 0) s.integrator.tolerance = tolerance;
    return s;
}

std::unique_ptr<Simulation> simulationOn(const Scene& scene, const ParticleState& initial, const std::string& backend, int threads,
                                         SimulationLimits limits) {
    BackendChoice choice;
    choice.name = backend;
    choice.threads = threads;
    return std::make_unique<Simulation>(scene, makeBackend(backendChoiceFor(scene, choice)), initial, limits);
}

void advanceTo(Simulation& sim, double t) {
    const double eps = 1e-12 * std::max(1.0, std::fabs(t));
    while (sim.time() < t - eps) {
        if (sim.scene().integrator.adaptive) sim.limitNextStep(t - sim.time());
        sim.step();
    }
}

double leastSquaresSlope(const std::vector<double>& t, const std::vector<double>& y) {
    const double n = double(t.size());
    if (t.size() < 2) return 0;
    double st = 0, sy = 0, stt = 0, sty = 0;
    for (size_t k = 0; k < t.size(); ++k) {
        st += t[k];
        sy += y[k];
        stt += t[k] * t[k];
        sty += t[k] * y[k];
    }
    const double d = n * stt - st * st;
    return d != 0 ? (n * sty - st * sy) / d : 0.0;
}

}  // namespace corebox
