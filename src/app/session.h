// The running simulation behind the window, the headless HUD and scripts: the SimulationHost that
// the panel's controls act on. Restarting or switching precision replaces the backend, so anything
// that holds on to it (the interop feed) checks generation().
#pragma once

#include <cstdint>
#include <memory>

#include "backend_factory.h"
#include "blow_up_recovery.h"
#include "initial_conditions.h"
#include "live_controls.h"
#include "simulation.h"

namespace corebox {

class Session final : public SimulationHost {
public:
    // Throws InputError (bad scene), DeviceError. `setupProgress` hears of long set-ups (and restarts).
    Session(const Scene& scene, const BackendChoice& backend, SimulationLimits limits = SimulationLimits{},
            SetupProgress setupProgress = nullptr);

    Simulation& simulation() { return *m_sim; }
    uint64_t generation() const { return m_generation; }
    // The automatic integrator's choice at the last restart of a scene with method = "auto" ("" otherwise).
    const std::string& integratorChoice() const { return m_integratorChoice; }

    const Scene& runningScene() const override { return m_sim->scene(); }
    void applyStepParameters(const StepParameters& parameters) override { m_sim->setStepParameters(parameters); }
    void applyThermostat(const ThermostatDef& thermostat) override { m_sim->setThermostat(thermostat); }
    void switchPrecision(Precision precision) override;
    void restart(const Scene& scene) override;
    // After a blow-up: the simulation rebuilt at `recovery`'s point with dt halved (a new generation).
    // Throws InstabilityError when recovery gives up.
    RecoveryEvent recover(BlowUpRecovery& recovery, const InstabilityError& error);

private:
    BackendChoice m_backend;
    SimulationLimits m_limits;
    SetupProgress m_setupProgress;
    std::unique_ptr<Simulation> m_sim;
    uint64_t m_generation = 0;
    std::string m_integratorChoice;
};

}  // namespace corebox
