#include "study.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>

#include "backend_factory.h"
#include "errors.h"
#include "simulation.h"
#include "study_runs.h"
#include "vocabulary.h"

namespace corebox {
namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

constexpr int kEnergySamples = 50;          // observations of the conserved sum over L
constexpr int kStabilitySamples = 20;       // observations (drift checks) over a stability trial
constexpr int kMaxDoublings = 12;           // stability: steps tried up to 2^12 times the scene's
constexpr int kMaxHalvings = 4;             // ... and down to 1/16 of it
constexpr int kBisections = 10;             // then bisected to 2^-10 of the bracket
constexpr double kCapHitShare = 0.01;       // a trial whose rounds hit the cap more often fails

bool isAdaptiveCapable(Method m) { return m == Method::Dp5; }

Scene sceneFor(const Scene& base, Method method, Precision precision, double dt, double tolerance) {
    return sceneWithIntegrator(base, method, precision, dt, tolerance);
}

std::unique_ptr<Simulation> simulationFor(const Scene& scene, const ParticleState& initial, const StudyOptions& o,
                                          SimulationLimits limits = SimulationLimits{}) {
    return simulationOn(scene, initial, o.backend, o.threads, limits);
}

double rmsDistance(const ParticleState& a, const ParticleState& b) {
    double sum = 0;
    for (size_t i = 0; i < a.size(); ++i) sum += norm2(a.position[i] - b.position[i]);
    return a.size() > 0 ? std::sqrt(sum / double(a.size())) : 0.0;
}

// The position state at T of a fixed-step run at step dt (rounded to divide T).
ParticleState trajectoryAt(const Scene& base, const ParticleState& initial, const StudyOptions& o, Method method, double dt,
                           double horizon) {
    const int64_t steps = std::max<int64_t>(1, std::llround(horizon / dt));
    auto sim = simulationFor(sceneFor(base, method, Precision::Fp64, horizon / double(steps), 0), initial, o);
    for (int64_t s = 0; s < steps; ++s) sim->step();
    return sim->state();
}

// One run of the ladder: to T for the state error, on to L for the energy and the cost.
StudyRun ladderRun(const Scene& base, const ParticleState& initial, const StudyOptions& o, const ParticleState& reference, Method method,
                   Precision precision, double dt, double tolerance, double horizon, double longRun) {
    StudyRun r;
    r.method = method;
    r.precision = precision;
    r.tolerance = tolerance;
    r.stateError = std::numeric_limits<double>::quiet_NaN();
    r.energyErrorMax = std::numeric_limits<double>::quiet_NaN();
    r.energyDriftRate = std::numeric_limits<double>::quiet_NaN();
    // A fixed step that divides T divides L too (L is a whole number of T's when chosen by default;
    // otherwise the run's last observation lands within a step of L).
    const double step = tolerance > 0 ? dt : horizon / double(std::max<int64_t>(1, std::llround(horizon / dt)));
    r.dt = step;
    try {
        auto sim = simulationFor(sceneFor(base, method, precision, step, tolerance), initial, o);
        const double e0 = sim->observe().conserved();
        const double scale = sim->energyScale();
        const int64_t passes0 = sim->backend().forceCounters().fullPasses;
        std::vector<double> times{0}, errors{0};
        double wall = 0;
        bool stateTaken = false;
        for (int k = 1; k <= kEnergySamples; ++k) {
            const double target = longRun * double(k) / kEnergySamples;
            // Take the state at T on the way (T is one of the sample times or between two).
            if (!stateTaken && target >= horizon - 1e-12 * horizon) {
                const Clock::time_point start = Clock::now();
                advanceTo(*sim, horizon);
                sim->backend().finish();
                wall += secondsSince(start);
                r.stateError = rmsDistance(sim->state(), reference);
                stateTaken = true;
            }
            const Clock::time_point start = Clock::now();
            advanceTo(*sim, target);
            sim->backend().finish();
            wall += secondsSince(start);
            const double e = (sim->observe().conserved() - e0) / scale;
            times.push_back(sim->time());
            errors.push_back(e);
        }
        double worst = 0;
        for (double e : errors) worst = std::max(worst, std::fabs(e));
        r.energyErrorMax = worst;
        r.energyDriftRate = leastSquaresSlope(times, errors);
        r.forcePassesPerTime = double(sim->backend().forceCounters().fullPasses - passes0) / sim->time();
        r.wallSecondsPerTime = wall / sim->time();
        if (tolerance > 0) r.dt = sim->time() / double(std::max<int64_t>(1, sim->stepIndex()));
    } catch (const InstabilityError& e) {
        r.outcome = instabilityKind(e.what());
        r.message = e.what();
    }
    return r;
}

// Whether a fixed-step run at dt survives L; on failure, its kind in `failure`.
bool survives(const Scene& base, const ParticleState& initial, const StudyOptions& o, Method method, Precision precision, double dt,
              double longRun, std::string& failure) {
    try {
        SimulationLimits limits;
        limits.maxEnergyDrift = o.driftLimit;
        auto sim = simulationFor(sceneFor(base, method, precision, dt, 0), initial, o, limits);
        sim->observe();
        const int64_t steps = std::max<int64_t>(1, int64_t(std::ceil(longRun / dt)));
        for (int64_t s = 1; s <= steps; ++s) {
            sim->step();
            if (s % std::max<int64_t>(1, steps / kStabilitySamples) == 0 || s == steps) sim->observe();
        }
        if (double(sim->roundCapHits()) > kCapHitShare * double(steps)) {
            failure = "rounds_capped";
            return false;
        }
        return true;
    } catch (const InstabilityError& e) {
        failure = instabilityKind(e.what());
        return false;
    }
}

StabilityLimit stabilityLimit(const Scene& base, const ParticleState& initial, const StudyOptions& o, Method method, Precision precision,
                              double longRun) {
    StabilityLimit limit;
    limit.method = method;
    limit.precision = precision;
    std::string failure;
    double dt = base.integrator.dt;
    if (survives(base, initial, o, method, precision, dt, longRun, failure)) {
        limit.stableDt = dt;
        for (int k = 0; k < kMaxDoublings; ++k) {
            dt *= 2;
            if (!survives(base, initial, o, method, precision, dt, longRun, failure)) {
                limit.unstableDt = dt;
                limit.failure = failure;
                break;
            }
            limit.stableDt = dt;
        }
    } else {
        limit.unstableDt = dt;
        limit.failure = failure;
        for (int k = 0; k < kMaxHalvings; ++k) {
            dt /= 2;
            if (survives(base, initial, o, method, precision, dt, longRun, failure)) {
                limit.stableDt = dt;
                break;
            }
            limit.unstableDt = dt;
            limit.failure = failure;
        }
    }
    if (limit.stableDt <= 0 || limit.unstableDt <= 0) return limit;  // no bracket: a bound only
    for (int k = 0; k < kBisections; ++k) {
        const double mid = 0.5 * (limit.stableDt + limit.unstableDt);
        if (survives(base, initial, o, method, precision, mid, longRun, failure)) {
            limit.stableDt = mid;
        } else {
            limit.unstableDt = mid;
            limit.failure = failure;
        }
    }
    return limit;
}

}  // namespace

double observedOrder(const StudyResult& result, Method method, Precision precision) {
    const double floor = std::max(10.0 * result.referenceError, 1e-12);
    std::vector<double> x, y;
    for (const StudyRun& run : result.runs) {
        if (run.method != method || run.precision != precision || run.tolerance > 0 || run.outcome != "ok") continue;
        if (!(run.stateError > floor && run.stateError < 1e-2)) continue;
        x.push_back(std::log(run.dt));
        y.push_back(std::log(run.stateError));
    }
    return x.size() >= 2 ? leastSquaresSlope(x, y) : std::numeric_limits<double>::quiet_NaN();
}

StudyResult runStudy(const Scene& sceneAsGiven, const ParticleState& initial, const StudyOptions& o,
                     const std::function<void(int, int, const std::string&)>& progress) {
    Scene scene = sceneAsGiven;
    scene.thermostat.kind = ThermostatKind::None;  // the design note says why
    if (o.precisions.empty()) throw InputError("study: --precision lists no precision");
    if (o.dtFactors.empty()) throw InputError("study: --dt lists no step");
    for (double f : o.dtFactors) {
        if (!(f > 0) || !std::isfinite(f)) throw InputError("study: --dt factors must be finite numbers > 0");
    }
    std::vector<Method> methods = o.methods;
    if (methods.empty()) {
        for (const auto& term : methodTable()) methods.push_back(term.value);
    }
    StudyResult result;
    result.methods = methods;
    result.thermostat = sceneAsGiven.thermostat.kind == ThermostatKind::None
                            ? "none"
                            : std::string("off (the scene's ") + thermostatTable().name(sceneAsGiven.thermostat.kind) + " is switched off)";
    result.precisions = o.precisions;
    result.particles = int64_t(initial.size());
    const double sceneDt = scene.integrator.dt;
    result.horizon = o.horizon > 0 ? o.horizon : 100 * sceneDt;
    result.longRun = o.longRun > 0 ? o.longRun : 10 * result.horizon;
    if (result.longRun < result.horizon) throw InputError("study: the long run (--long) must be at least the horizon (--horizon)");

    int adaptiveRuns = 0;
    for (Method m : methods) adaptiveRuns += isAdaptiveCapable(m) ? int(o.tolerances.size()) : 0;
    const int total = 2 + int(methods.size() * o.precisions.size() * o.dtFactors.size()) + adaptiveRuns * int(o.precisions.size()) +
                      (o.stability ? int(methods.size() * o.precisions.size()) : 0);
    int done = 0;
    auto tick = [&](const std::string& what) {
        if (progress) progress(done, total, what);
        ++done;
    };

    // The reference and its check.
    const double smallest = sceneDt * *std::min_element(o.dtFactors.begin(), o.dtFactors.end());
    const double dtRef = smallest / 4;
    tick("reference (hairer10 fp64)");
    const ParticleState reference = trajectoryAt(scene, initial, o, Method::Hairer10, dtRef, result.horizon);
    tick("reference check (half its step)");
    const ParticleState check = trajectoryAt(scene, initial, o, Method::Hairer10, dtRef / 2, result.horizon);
    result.referenceError = rmsDistance(reference, check);
    char text[160];
    std::snprintf(text, sizeof text, "hairer10 fp64 dt = %.6g (checked at dt = %.6g)", dtRef, dtRef / 2);
    result.reference = text;
    {
        BackendChoice choice;
        choice.name = o.backend;
        choice.threads = o.threads;
        result.device = makeBackend(backendChoiceFor(scene, choice))->deviceName();
    }

    for (Method m : methods) {
        for (Precision p : o.precisions) {
            for (double f : o.dtFactors) {
                std::snprintf(text, sizeof text, "%s %s dt = %.4g", methodName(m), precisionTable().name(p), f * sceneDt);
                tick(text);
                result.runs.push_back(ladderRun(scene, initial, o, reference, m, p, f * sceneDt, 0, result.horizon, result.longRun));
            }
            if (!isAdaptiveCapable(m)) continue;
            for (double tol : o.tolerances) {
                std::snprintf(text, sizeof text, "%s %s adaptive tolerance %.0e", methodName(m), precisionTable().name(p), tol);
                tick(text);
                result.runs.push_back(ladderRun(scene, initial, o, reference, m, p, sceneDt, tol, result.horizon, result.longRun));
            }
        }
    }
    if (o.stability) {
        for (Method m : methods) {
            for (Precision p : o.precisions) {
                std::snprintf(text, sizeof text, "stability of %s %s", methodName(m), precisionTable().name(p));
                tick(text);
                result.limits.push_back(stabilityLimit(scene, initial, o, m, p, result.longRun));
            }
        }
    }
    if (progress) progress(total, total, "done");
    return result;
}

}  // namespace corebox
