#include "auto_integrator.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>

#include "blow_up_recovery.h"
#include "errors.h"
#include "initial_conditions.h"
#include "integration_driver.h"
#include "study_runs.h"
#include "vocabulary.h"

namespace corebox {
namespace {

using Clock = std::chrono::steady_clock;

constexpr Method kCandidates[] = {Method::Verlet, Method::ForestRuth, Method::Pefrl, Method::BlanesMoan,
                                  Method::Yoshida6, Method::Yoshida8, Method::Rk4};
constexpr double kDtFactors[] = {8, 4, 2, 1, 0.5, 0.25, 0.125, 0.0625};
constexpr int kEnergySamples = 10;
constexpr double kDefaultPilotSteps = 500;
constexpr double kMargin = 0.5;  // a pilot run must show half the tolerance: a longer run sees larger excursions

struct Candidate {
    Method method;
    Precision precision;
    double dt;
    double predictedCost;  // force passes per unit time
};

bool hasPairForces(const Scene& scene) {
    for (const SpeciesDef& s : scene.species)
        if (s.epsilon > 0) return true;
    return false;
}

// A trial that would take longer than `wallLimit` cannot beat the best so far: it stops there.
PilotTrial runTrial(const Scene& scene, const ParticleState& initial, const AutoIntegratorOptions& o, const Candidate& c, double pilotTime,
                    double wallLimit) {
    PilotTrial t;
    t.method = c.method;
    t.precision = c.precision;
    t.dt = c.dt;
    const Clock::time_point start = Clock::now();
    auto elapsed = [&] { return std::chrono::duration<double>(Clock::now() - start).count(); };
    try {
        auto sim = simulationOn(sceneWithIntegrator(scene, c.method, c.precision, c.dt), initial, o.backend, o.threads);
        const double e0 = sim->observe().conserved();
        const double scale = sim->energyScale();
        const int64_t passes0 = sim->backend().forceCounters().fullPasses;
        double worst = 0;
        for (int k = 1; k <= kEnergySamples; ++k) {
            const double target = pilotTime * double(k) / kEnergySamples;
            while (sim->time() < target - 1e-12 * target) {
                sim->step();
                if (elapsed() > wallLimit) {
                    t.outcome = "too_slow";
                    t.errorPerTime = std::numeric_limits<double>::infinity();
                    t.wallSecondsPerTime = elapsed() / sim->time();
                    return t;
                }
            }
            worst = std::max(worst, std::fabs(sim->observe().conserved() - e0) / scale);
        }
        sim->backend().finish();
        t.errorPerTime = worst / sim->time();
        t.forcePassesPerTime = double(sim->backend().forceCounters().fullPasses - passes0) / sim->time();
        t.wallSecondsPerTime = elapsed() / sim->time();
    } catch (const InstabilityError& e) {
        t.outcome = instabilityKind(e.what());
        t.errorPerTime = std::numeric_limits<double>::infinity();
    }
    return t;
}

std::string describe(const PilotTrial& t) {
    char text[200];
    std::snprintf(text, sizeof text, "%s %s dt = %g", methodName(t.method), precisionName(t.precision), t.dt);
    return text;
}

}  // namespace

AutoIntegratorChoice chooseIntegrator(const Scene& scene, const ParticleState& initial, const AutoIntegratorOptions& o) {
    AutoIntegratorChoice choice;
    choice.tolerance = scene.integrator.tolerance;
    choice.integrator = scene.integrator;
    choice.integrator.automatic = false;
    choice.integrator.adaptive = false;
    char line[600];
    if (!hasPairForces(scene)) {
        choice.integrator.method = Method::Verlet;
        choice.met = true;
        choice.chosen.method = Method::Verlet;
        choice.chosen.precision = scene.integrator.precision;
        choice.chosen.dt = scene.integrator.dt;
        choice.summary = "integrator auto: verlet " + std::string(precisionName(scene.integrator.precision)) + " dt = " +
                         std::to_string(scene.integrator.dt) +
                         " without a pilot: no pair forces, so the accelerations are constant (gravity or none) and verlet "
                         "integrates them exactly between collisions";
        return choice;
    }

    // The precisions: the scene's, and on a GPU the other one too.
    std::vector<Precision> precisions{scene.integrator.precision};
    {
        BackendChoice probe;
        probe.name = o.backend;
        probe.threads = o.threads;
        if (makeBackend(backendChoiceFor(scene, probe))->name() == "cuda")
            precisions = {Precision::Fp32, Precision::Fp64};  // fp32 first at equal cost
    }
    std::vector<Candidate> candidates;
    for (Method m : kCandidates)
        for (double f : kDtFactors)
            for (Precision p : precisions) {
                const double dt = scene.integrator.dt * f;
                candidates.push_back({m, p, dt, double(forcePassesPerStepOf(m)) / dt});
            }
    // Cheapest first by force passes; the pilot then measures what each really costs here.
    std::stable_sort(candidates.begin(), candidates.end(),
                     [](const Candidate& a, const Candidate& b) { return a.predictedCost < b.predictedCost; });

    const double pilotTime = o.pilotTime > 0 ? o.pilotTime : kDefaultPilotSteps * scene.integrator.dt;
    const Clock::time_point start = Clock::now();
    auto spent = [&] { return std::chrono::duration<double>(Clock::now() - start).count(); };
    bool budgetSpent = false;
    const PilotTrial* best = nullptr;   // the fastest run that met the tolerance
    double secondsPerPass = 0;          // the fastest measured: a lower bound of any run's cost per pass
    choice.trials.reserve(candidates.size());
    for (const Candidate& c : candidates) {
        const double remaining = o.budgetSeconds - spent();
        if (remaining <= 0) {
            budgetSpent = true;
            break;
        }
        // Later candidates need more force passes per unit time: once even their passes at the fastest
        // rate seen cost more than the best run, none of them can win.
        const double lowerBound = c.predictedCost * pilotTime * secondsPerPass;
        if (best && lowerBound >= best->wallSecondsPerTime * pilotTime) break;
        const double wallLimit = best ? std::min(remaining, best->wallSecondsPerTime * pilotTime) : remaining;
        PilotTrial t = runTrial(scene, initial, o, c, pilotTime, wallLimit);
        t.meets = t.outcome == "ok" && t.errorPerTime <= kMargin * choice.tolerance;
        if (t.outcome == "ok" && t.forcePassesPerTime > 0) {
            const double rate = t.wallSecondsPerTime / t.forcePassesPerTime;
            secondsPerPass = secondsPerPass > 0 ? std::min(secondsPerPass, rate) : rate;
        }
        choice.trials.push_back(t);
        if (t.meets && (!best || t.wallSecondsPerTime < best->wallSecondsPerTime)) best = &choice.trials.back();
    }
    choice.pilotSeconds = spent();
    choice.piloted = true;

    // Runs within timing noise (15%) of the fastest are a tie, won by fewer force passes: the same
    // scene then picks the same run from one start to the next.
    const PilotTrial* chosen = best;
    for (const PilotTrial& t : choice.trials)
        if (best && t.meets && t.wallSecondsPerTime <= 1.15 * best->wallSecondsPerTime && t.forcePassesPerTime < chosen->forcePassesPerTime)
            chosen = &t;
    choice.met = best != nullptr;
    if (!chosen) {
        for (const PilotTrial& t : choice.trials)
            if (t.outcome == "ok" && (!chosen || t.errorPerTime < chosen->errorPerTime)) chosen = &t;
    }
    if (!chosen)
        throw InputError("integrator: method = \"auto\": every pilot run (" + std::to_string(choice.trials.size()) +
                         ") blew up; give a method and a smaller dt");
    choice.chosen = *chosen;
    choice.integrator.method = chosen->method;
    choice.integrator.precision = chosen->precision;
    choice.integrator.dt = chosen->dt;
    // The cheapest run that missed, for the reason.
    std::string missed;
    for (const PilotTrial& t : choice.trials) {
        if (&t == chosen || t.meets || t.outcome == "too_slow") continue;
        char m[200];
        if (t.outcome == "ok") std::snprintf(m, sizeof m, "; cheaper runs missed it (first: %s, %.2g per unit time)", describe(t).c_str(), t.errorPerTime);
        else std::snprintf(m, sizeof m, "; cheaper runs missed it (first: %s, %s)", describe(t).c_str(), t.outcome.c_str());
        missed = m;
        break;
    }
    if (choice.met) {
        std::snprintf(line, sizeof line,
                      "integrator auto (energy error <= %g per unit time): %s, %.2g per unit time at %.4g force passes and %.3g s "
                      "per unit time, the fastest of %zu pilot runs over t = %g (%.1f s)%s",
                      choice.tolerance, describe(*chosen).c_str(), chosen->errorPerTime, chosen->forcePassesPerTime,
                      chosen->wallSecondsPerTime, choice.trials.size(), pilotTime, choice.pilotSeconds, missed.c_str());
    } else {
        std::snprintf(line, sizeof line,
                      "integrator auto: warning: no pilot run met an energy error of %g per unit time (%zu runs over t = %g, %.1f s%s); "
                      "running the most accurate tried, %s at %.2g per unit time",
                      choice.tolerance, choice.trials.size(), pilotTime, choice.pilotSeconds, budgetSpent ? ", budget spent" : "",
                      describe(*chosen).c_str(), chosen->errorPerTime);
    }
    choice.summary = line;
    return choice;
}

Scene resolveAutomaticIntegrator(const Scene& scene, const BackendChoice& backend, bool quiet, std::string* summary) {
    if (summary) summary->clear();
    if (!scene.integrator.automatic) return scene;
    AutoIntegratorOptions o;
    o.backend = backend.name;
    o.threads = backend.threads;
    if (!quiet && hasPairForces(scene))
        std::fprintf(stderr, "[corebox] integrator auto: a pilot study of the methods at energy error <= %g per unit time ...\n",
                     scene.integrator.tolerance);
    const AutoIntegratorChoice choice = chooseIntegrator(scene, makeInitialState(scene), o);
    if (!quiet) std::fprintf(stderr, "[corebox] %s\n", choice.summary.c_str());
    if (summary) *summary = choice.summary;
    Scene resolved = scene;
    resolved.integrator = choice.integrator;
    return resolved;
}

}  // namespace corebox
