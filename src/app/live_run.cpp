#include "live_run.h"

#include <cmath>
#include <cstdio>

#include "errors.h"
#include "interruption.h"
#include "study_curves.h"
#include "study_runs.h"
#include "vocabulary.h"
#include "observables.h"
#include "speed_distributions.h"

namespace corebox {

using Clock = std::chrono::steady_clock;

LiveRun::LiveRun(const Scene& scene, const BackendChoice& backend, LiveRunOptions options, SimulationLimits limits)
    : m_options(std::move(options)), m_session(scene, backend, limits, m_options.setupProgress), m_controls(m_session), m_rateStart(Clock::now()) {
    if (!m_options.observablesPath.empty()) {
        m_observables = std::make_unique<ObservablesOutput>(m_options.observablesPath);
        m_observables->header(scene);
        if (m_options.recover) m_observables->hold();
    }
    if (m_options.recover) m_recovery.emplace(RecoveryPolicy{8, m_options.recoveryPointSeconds});
    if (!m_options.studyPath.empty()) {
        m_accuracy.studySource = m_options.studyPath;
        m_accuracy.study = loadStudyCurves(m_options.studyPath);  // --study: a bad file is an input error
    } else if (const std::string found = findStudyFile(scene, simulation().backend().name()); !found.empty()) {
        try {
            m_accuracy.study = loadStudyCurves(found);
            m_accuracy.studySource = found;
        } catch (const InputError& e) {
            std::fprintf(stderr, "[corebox] warning: %s; the speed-vs-accuracy panel shows no study\n", e.what());
        }
    }
    m_performance.backend = simulation().backend().name();
    m_performance.device = simulation().backend().deviceName();
    m_performance.integrator = m_options.integratorChoice;
    noteForceModel();
    observe(0);
    m_conserved0 = m_lastRow.conserved();
    refreshSpeedDistributions();
}

void LiveRun::observe(int64_t stepsSinceLast) {
    const Clock::time_point t = Clock::now();
    m_lastRow = simulation().observe();
    m_observeSeconds += std::chrono::duration<double>(Clock::now() - t).count();
    const Scene& s = simulation().scene();
    m_history.push(m_lastRow, m_conserved0 != 0 ? m_conserved0 : m_lastRow.conserved(),
                   s.thermostat.kind == ThermostatKind::None ? 0.0 : s.thermostat.temperature, stepsSinceLast);
    if (m_observables) m_observables->row(m_lastRow);
    m_lastObservedStep = simulation().stepIndex();
    keepRecoveryPoint(false);
    trackAccuracy();
}

void LiveRun::trackAccuracy() {
    Simulation& sim = simulation();
    const IntegratorDef& in = sim.scene().integrator;
    char label[120];
    if (in.adaptive) std::snprintf(label, sizeof label, "%s %s tol %g", methodName(in.method), precisionName(in.precision), in.tolerance);
    else std::snprintf(label, sizeof label, "%s %s dt %g", methodName(in.method), precisionName(in.precision), in.dt);
    const int64_t passes = sim.backend().forceCounters().fullPasses;
    const bool fresh = m_segment.label != label || m_segment.generation != m_session.generation() || passes < m_segment.passes0 ||
                       sim.time() < m_segment.time0;
    if (fresh) {
        if (!m_accuracy.live.empty()) m_accuracy.live.back().running = false;
        if (m_accuracy.live.size() >= 12) m_accuracy.live.erase(m_accuracy.live.begin());
        m_accuracy.live.push_back(AccuracyPoint{label, 0, 0, true});
        m_segment = AccuracySegment{label, m_session.generation(), passes, sim.time(), {}, {}};
    }
    m_segment.times.push_back(sim.time());
    m_segment.energies.push_back(m_lastRow.conserved() / sim.energyScale());
    const double elapsed = sim.time() - m_segment.time0;
    if (m_segment.times.size() < 3 || !(elapsed > 0)) return;
    AccuracyPoint& point = m_accuracy.live.back();
    point.cost = double(passes - m_segment.passes0) / elapsed;
    point.driftRate = std::fabs(leastSquaresSlope(m_segment.times, m_segment.energies));
}

// Right after an observation passed the checks: a point when one is due, or at once when the session
// was replaced (a reset, a precision switch) since the last one, whose point belongs to another run.
void LiveRun::keepRecoveryPoint(bool force) {
    if (!m_recovery) return;
    const bool replaced = m_recoveryGeneration != m_session.generation() || !m_recovery->hasPoint();
    if (force || replaced) {
        m_recovery->remember(simulation());
    } else if (!m_recovery->rememberIfDue(simulation())) {
        return;
    }
    m_recoveryGeneration = m_session.generation();
    if (m_observables) m_observables->release();
}

void LiveRun::stepOnce() {
    // A session replaced by an edit must not fall back to a point from before it.
    if (m_recovery && m_recoveryGeneration != m_session.generation()) keepRecoveryPoint(true);
    const Clock::time_point t = Clock::now();
    const StepReport r = simulation().step();
    m_stepSeconds += std::chrono::duration<double>(Clock::now() - t).count();
    m_forceSeconds += r.secondsForces;
    m_integrateSeconds += r.secondsIntegrate;
    m_collideSeconds += r.secondsCollide;
    ++m_rateSteps;
    const int64_t step = simulation().stepIndex();
    if (step % m_options.observeEvery == 0) observe(step - m_lastObservedStep);
}

void LiveRun::recoverFrom(const InstabilityError& error) {
    const RecoveryEvent event = m_session.recover(*m_recovery, error);  // throws when it gives up
    m_recoveryGeneration = m_session.generation();
    if (m_observables) m_observables->discardAfter(event.resumedStep);
    m_history.dropAfter(event.resumedTime);
    m_lastObservedStep = event.resumedStep;
    m_recoveries.push_back(event);
    status = "recovered from a blow-up at " + event.summary();
    std::fprintf(stderr, "[corebox] %s\n", status.c_str());
}

ScriptEffects LiveRun::advance(int64_t steps, double budgetSeconds) {
    ScriptEffects effects;
    const Clock::time_point start = Clock::now();
    auto runDue = [&]() {
        if (!m_options.script) return;
        for (const ScriptCommand& c : m_options.script->due(simulation().stepIndex())) {
            const ScriptEffects e = runScriptCommand(c, m_options.script->path(), m_controls, m_display, !m_options.quiet);
            effects.quit = effects.quit || e.quit;
            effects.reset = effects.reset || e.reset;
            if (!e.screenshotPath.empty()) effects.screenshotPath = e.screenshotPath;
        }
    };
    runDue();
    for (int64_t k = 0; k < steps && !effects.quit && effects.screenshotPath.empty() && !effects.reset; ++k) {
        if (m_recovery) {
            try {
                stepOnce();
            } catch (const InstabilityError& e) {
                recoverFrom(e);
            }
        } else {
            stepOnce();
        }
        runDue();
        if (budgetSeconds > 0 && std::chrono::duration<double>(Clock::now() - start).count() > budgetSeconds) break;
        if (interruptRequested()) break;
    }
    return effects;
}

std::string LiveRun::reset() {
    const std::string error = m_controls.reset();
    if (!error.empty()) return error;
    m_history.clear();
    m_lastObservedStep = 0;
    if (m_observables) m_observables->release();  // the rows of the run before the reset
    observe(0);
    m_conserved0 = m_lastRow.conserved();
    m_performance.backend = simulation().backend().name();
    if (!m_session.integratorChoice().empty()) m_performance.integrator = m_session.integratorChoice();
    refreshSpeedDistributions();
    return "";
}

void LiveRun::refreshSpeedDistributions() { measureSpeedDistributions(simulation(), m_lastRow, m_speeds); }

// Said at the start and again whenever a live edit (a cutoff in the panel) changes the choice.
void LiveRun::noteForceModel() {
    const std::string forces = simulation().forceChoice().summary();
    if (forces == m_performance.forces) return;
    m_performance.forces = forces;
    if (!m_options.quiet) std::fprintf(stderr, "[corebox] forces: %s\n", forces.c_str());
}

void LiveRun::recordFrame(double msInterop, double msRender) {
    noteForceModel();
    ++m_rateFrames;
    const double elapsed = std::chrono::duration<double>(Clock::now() - m_rateStart).count();
    m_performance.msInterop = msInterop;
    m_performance.msRender = msRender;
    m_performance.stepsPerFrame = m_display.stepsPerFrame;
    if (elapsed < 0.5) return;
    PerformanceData& p = m_performance;
    p.stepsPerSecond = double(m_rateSteps) / elapsed;
    p.framesPerSecond = double(m_rateFrames) / elapsed;
    const double n = double(simulation().particleCount());
    const Method m = simulation().scene().integrator.method;
    const double passes = double(forcePassesPerStepOf(m));
    p.pairForces = false;
    for (const SpeciesDef& s : simulation().scene().species) p.pairForces = p.pairForces || s.epsilon > 0;
    p.pairInteractionsPerSecond = p.pairForces ? p.stepsPerSecond * passes * n * (n - 1) : 0.0;
    const double perFrame = m_rateFrames > 0 ? 1e3 / double(m_rateFrames) : 0.0;
    p.msStep = perFrame * m_stepSeconds;
    p.msForce = perFrame * m_forceSeconds;
    p.msIntegrate = perFrame * m_integrateSeconds;
    p.msCollide = perFrame * m_collideSeconds;
    p.msObserve = perFrame * m_observeSeconds;
    m_rateStart = Clock::now();
    m_rateSteps = m_rateFrames = 0;
    m_stepSeconds = m_observeSeconds = m_forceSeconds = m_integrateSeconds = m_collideSeconds = 0;
}

void LiveRun::observeNow() {
    const int64_t step = simulation().stepIndex();
    if (step != m_lastObservedStep) observe(step - m_lastObservedStep);
}

void LiveRun::finish() {
    if (m_observables) m_observables->commit();
    m_observables.reset();
}

}  // namespace corebox
