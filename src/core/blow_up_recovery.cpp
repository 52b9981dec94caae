#include "blow_up_recovery.h"

#include <cstdio>

namespace corebox {

std::string instabilityKind(const std::string& message) {
    auto has = [&](const char* what) { return message.find(what) != std::string::npos; };
    if (has("non-finite") || has("not finite")) return "non_finite";
    if (has("escaped")) return "escape";
    if (has("runaway")) return "runaway";
    if (has("energy drift")) return "energy_growth";
    if (has("adaptive")) return "adaptive_failed";
    if (has("collision rounds")) return "rounds_capped";
    return "failed";
}

std::string RecoveryEvent::summary() const {
    char text[400];
    if (toleranceAfter > 0) {
        std::snprintf(text, sizeof text, "step %lld (%s): back to step %lld, %s %s tolerance %g -> %g, dt %g -> %g", (long long)failedStep,
                      kind.c_str(), (long long)resumedStep, methodName(method), precisionName(precision), toleranceBefore, toleranceAfter,
                      dtBefore, dtAfter);
    } else {
        std::snprintf(text, sizeof text, "step %lld (%s): back to step %lld, %s %s dt %g -> %g", (long long)failedStep, kind.c_str(),
                      (long long)resumedStep, methodName(method), precisionName(precision), dtBefore, dtAfter);
    }
    return text;
}

BlowUpRecovery::BlowUpRecovery(RecoveryPolicy policy) : m_policy(policy) {}

void BlowUpRecovery::remember(const Simulation& sim) {
    m_point = Point{sim.scene(), sim.checkpoint()};
    m_taken = std::chrono::steady_clock::now();
    m_attempts = 0;
}

bool BlowUpRecovery::rememberIfDue(const Simulation& sim) {
    if (m_point && sim.stepIndex() <= m_point->checkpoint.step) return false;
    if (m_point && m_policy.minSeconds > 0 &&
        std::chrono::duration<double>(std::chrono::steady_clock::now() - m_taken).count() < m_policy.minSeconds)
        return false;
    remember(sim);
    return true;
}

RecoveryEvent BlowUpRecovery::recover(std::unique_ptr<Simulation>& sim, const InstabilityError& error, const BackendMaker& makeBackend) {
    if (!m_point) throw InstabilityError(std::string(error.what()) + " (no good state to go back to)");
    if (m_attempts >= m_policy.maxAttempts) {
        throw InstabilityError(std::string(error.what()) + " (recovery gave up: " + std::to_string(m_attempts) + " halvings of dt from step " +
                               std::to_string(m_point->checkpoint.step) + " did not get past it)");
    }
    RecoveryEvent event;
    event.failedStep = sim->stepIndex();
    event.failedTime = sim->time();
    event.kind = instabilityKind(error.what());
    event.message = error.what();
    const Scene& failing = sim->scene();
    event.method = failing.integrator.method;
    event.precision = failing.integrator.precision;
    StepParameters next = stepParametersOf(failing);
    const ThermostatDef thermostat = failing.thermostat;
    event.dtBefore = next.integrator.dt;
    next.integrator.dt *= 0.5;
    event.dtAfter = next.integrator.dt;
    if (next.integrator.adaptive) {
        event.toleranceBefore = next.integrator.tolerance;
        next.integrator.tolerance *= 0.1;
        event.toleranceAfter = next.integrator.tolerance;
    }
    const SimulationLimits limits = sim->limits();
    auto rebuilt = std::make_unique<Simulation>(m_point->scene, makeBackend(m_point->scene), m_point->checkpoint, limits);
    rebuilt->setStepParameters(next);
    rebuilt->setThermostat(thermostat);
    sim = std::move(rebuilt);  // only now: a failure to rebuild leaves the failed simulation to report
    event.resumedStep = sim->stepIndex();
    event.resumedTime = sim->time();
    event.attempt = ++m_attempts;
    ++m_recoveries;
    return event;
}

}  // namespace corebox
