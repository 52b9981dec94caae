#include "session.h"

#include <utility>

#include "auto_integrator.h"

namespace corebox {

Session::Session(const Scene& scene, const BackendChoice& backend, SimulationLimits limits, SetupProgress setupProgress)
    : m_backend(backend), m_limits(limits), m_setupProgress(std::move(setupProgress)) {
    restart(scene);
}

void Session::switchPrecision(Precision precision) {
    BackendChoice choice = backendChoiceFor(m_sim->scene(), m_backend);
    choice.precision = precision;
    m_sim->replaceBackend(makeBackend(choice));
    StepParameters p = stepParametersOf(m_sim->scene());
    p.integrator.precision = precision;
    m_sim->setStepParameters(p);
    ++m_generation;
}

void Session::restart(const Scene& requested) {
    // A preset with method = "auto" gets its pilot study here (a scene from the command line arrives resolved).
    const Scene scene = resolveAutomaticIntegrator(requested, m_backend, false, &m_integratorChoice);
    const ParticleState initial = makeInitialState(scene, m_setupProgress);  // throws InputError before anything changes
    m_sim = std::make_unique<Simulation>(scene, makeBackend(backendChoiceFor(scene, m_backend)), initial, m_limits);
    ++m_generation;
}

RecoveryEvent Session::recover(BlowUpRecovery& recovery, const InstabilityError& error) {
    const RecoveryEvent event =
        recovery.recover(m_sim, error, [&](const Scene& scene) { return makeBackend(backendChoiceFor(scene, m_backend)); });
    ++m_generation;
    return event;
}

}  // namespace corebox
