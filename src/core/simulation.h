// A running simulation: one backend, the scene it runs, the step clock, the thermostat, the
// accumulated energy bookkeeping and the blow-up policy. Front ends (command line, window, tests)
// drive it with step() and observe(); live parameter edits go through setStepParameters() and
// setThermostat().
//
// step() is the one orchestration of a step for every backend: integrate (IntegrationDriver), resolve
// collisions in rounds (collision_rounds.h), thermostat, health check, each through the device
// interface of backend.h.
//
// Blow-up policy (exit code 3 at the command line): after every step the backend reports non-finite
// values and particles outside the box, and the kinetic energy is compared with a generous runaway
// bound; at every observation the conserved sum is compared with its initial value. A failure
// throws InstabilityError naming the step, the particles and the likely cause; the state before the
// failing step stays available from lastGoodState().
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "backend.h"
#include "checkpoint.h"
#include "force_model.h"
#include "integration_driver.h"
#include "observables.h"
#include "particle_state.h"
#include "pressure.h"
#include "scene.h"
#include "speed_statistics.h"
#include "step_report.h"

namespace corebox {

struct SimulationLimits {
    // Largest allowed |E_cons - E_cons(0)| as a fraction of the energy scale |K0| + |U0| (at least
    // the thermal energy 3N kT/2 of the target or initial temperature).
    double maxEnergyDrift = 0.5;
    // Kinetic energy above this many energy scales (plus the energy exchanged) is a runaway.
    double runawayFactor = 20.0;
};

class Simulation {
public:
    Simulation(Scene scene, std::unique_ptr<Backend> backend, const ParticleState& initial,
               SimulationLimits limits = SimulationLimits{});
    // Goes on from a checkpoint (checkpoint.h) exactly where it was taken; `scene` is the
    // checkpoint's scene (parseScene of its sceneToml) and the backend of the same kind and precision
    // for a bit-identical continuation.
    Simulation(Scene scene, std::unique_ptr<Backend> backend, const SimulationCheckpoint& checkpoint,
               SimulationLimits limits = SimulationLimits{});
    // Everything a restart needs (downloads the state).
    SimulationCheckpoint checkpoint() const;

    // One step: integrate + collide, thermostat, health check. Throws InstabilityError.
    StepReport step();
    // Full observables (O(N^2) potential and pair virial); resets the collision counters and the
    // pressure window. Throws InstabilityError
    // when the conserved energy drifted beyond the limit or a value is not finite.
    ObservablesRow observe();

    // Adaptive dp5: the next step is at most dt (a run that must end on a given time); no effect on
    // fixed steps.
    void limitNextStep(double dt) { m_driver.limitNextDt(dt); }

    // Whether step() times its phases (StepReport::secondsForces, Integrate, Collide: device marks on a
    // GPU, a few launches a step); on by default. Off, those stay 0 and a GPU step costs that less.
    void setPhaseTiming(bool on) {
        if (on && !m_phaseTiming) m_backend->phaseSeconds();  // what was left unread is no step of the next report
        m_phaseTiming = on;
    }

    void setStepParameters(const StepParameters& parameters);
    // An edit of the particles between steps (added, removed, moved, kicked; species added), as the
    // library's World makes them: `state` and `species` replace the old ones (species counts follow
    // the state), the force model is chosen again for the new count, and the energy the edit brought
    // in (E_kin + E_pot after minus before) is work done on the system like a live edit of the
    // potential: the conserved sum is re-based by it (parameterWork()). Returns that work [eps].
    // Throws InputError for a species index outside `species`.
    double replaceParticles(std::vector<SpeciesDef> species, const ParticleState& state);
    void setThermostat(const ThermostatDef& thermostat);
    // Replaces the backend (e.g. to switch precision), carrying the current state over.
    void replaceBackend(std::unique_ptr<Backend> backend);

    const Scene& scene() const { return m_scene; }
    Backend& backend() { return *m_backend; }
    int64_t stepIndex() const { return m_step; }
    double time() const { return m_time; }
    int64_t particleCount() const { return m_particleCount; }
    double dissipatedEnergy() const { return m_dissipated; }
    double thermostatEnergy() const { return m_thermostatEnergy; }
    int64_t roundCapHits() const { return m_roundCapHits; }
    double energyScale() const { return m_energyScale; }
    const SimulationLimits& limits() const { return m_limits; }
    // Work done on the system by live edits of the potential (gravity, mixing, cutoff) [eps]: the
    // conserved sum is re-based by it at each edit.
    double parameterWork() const { return m_parameterWork; }
    double lastKineticEnergy() const { return m_lastKinetic; }
    ParticleState state() const { return m_backend->state(); }
    void readState(ParticleState& out) const { m_backend->readState(out); }
    void readPositions(const PositionSink& sink) const { m_backend->readPositions(sink); }
    // The pair-force model in use and why (force_model.h); re-chosen at every parameter edit.
    const ForceChoice& forceChoice() const { return m_forceChoice; }
    ParticleState lastGoodState() const { return m_backend->snapshot(); }
    // The speed distribution of the current state (downloads the state).
    SpeedStatistics speedStatistics(const SpeedRequest& request) const;

private:
    void applyParameters();
    [[noreturn]] void fail(const std::string& what, const std::string& detail) const;
    std::string likelyCause() const;

    Scene m_scene;
    std::unique_ptr<Backend> m_backend;
    IntegrationDriver m_driver;
    SimulationLimits m_limits;
    int64_t m_particleCount = 0;
    int64_t m_step = 0;
    double m_time = 0;
    double m_dissipated = 0;
    double m_thermostatEnergy = 0;
    int64_t m_pairCollisions = 0;
    int64_t m_wallCollisions = 0;
    int64_t m_roundCapHits = 0;
    PressureGeometry m_pressureGeometry;
    double m_smallestContact = 0;  // DeviceModel::smallestContact of the running model (collision settings)
    PressureWindow m_pressureWindow;  // since the last observe()
    double m_energyScale = 1;
    double m_conserved0 = 0;
    double m_parameterWork = 0;
    double m_lastKinetic = 0;
    std::vector<int64_t> m_countPerSpecies;
    ForceChoice m_forceChoice;
    bool m_phaseTiming = true;
};

}  // namespace corebox
