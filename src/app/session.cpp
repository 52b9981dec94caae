#include "session.h"

#include "initial_conditions.h"

namespace corebox {

Session::Session(const Scene& scene, const BackendChoice& backend, SimulationLimits limits) : m_backend(backend), m_limits(limits) {
    restart(scene);
}

void Session::switchPrecision(Precision precision) {
    BackendChoice choice = m_backend;
    choice.precision = precision;
    m_sim->replaceBackend(makeBackend(choice));
    StepParameters p = stepParametersOf(m_sim->scene());
    p.integrator.precision = precision;
    m_sim->setStepParameters(p);
    ++m_generation;
}

void Session::restart(const Scene& scene) {
    const ParticleState initial = makeInitialState(scene);  // throws InputError before anything changes
    BackendChoice choice = m_backend;
    choice.precision = scene.integrator.precision;
    m_sim = std::make_unique<Simulation>(scene, makeBackend(choice), initial, m_limits);
    ++m_generation;
}

}  // namespace corebox
