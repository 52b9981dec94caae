// LiveControls: the edits a running simulation accepts (from the panel, a script or a test) and when
// each takes effect. Core code with no ImGui or GL, so it is unit-tested and the panel stays a view.
//
// Live settings (temperature and thermostat, mixing x_ij, integrator and dt, precision, restitution,
// gravity) reach the running simulation at once through the SimulationHost. Creation-time settings
// (counts, masses, radii, box, seed) are staged in a pending scene and only applied by reset(), which
// restarts the run from that scene.
//
// Every edit is checked by the rules a scene file meets (scene_validation.h): a live edit is applied
// to a copy of the running scene, which must validate; a staged value must meet its own rule (the
// whole pending scene is checked by reset()). A refused edit changes nothing; the setter returns why
// ("" when applied) and lastRefusal() keeps it for the panel.
#pragma once

#include <array>
#include <cstdint>
#include <string>

#include "scene.h"

namespace corebox {

// Implemented by the app around the running Simulation (and by tests).
class SimulationHost {
public:
    virtual ~SimulationHost() = default;
    virtual const Scene& runningScene() const = 0;
    virtual void applyStepParameters(const StepParameters& parameters) = 0;
    virtual void applyThermostat(const ThermostatDef& thermostat) = 0;
    virtual void switchPrecision(Precision precision) = 0;  // keeps the state
    virtual void restart(const Scene& scene) = 0;          // new initial state from the scene
};

class LiveControls {
public:
    explicit LiveControls(SimulationHost& host);

    // ---- live ----
    std::string setTargetTemperature(double kT);
    std::string setThermostatKind(ThermostatKind kind);  // None switches it off
    std::string setThermostatTau(double tau);
    std::string setMixing(size_t i, size_t j, double x);  // symmetric: sets x_ij and x_ji
    std::string setLikeUnlikeMixing(double like, double unlike);
    std::string setMethod(Method method);
    std::string setDt(double dt);
    std::string setPrecision(Precision precision);
    std::string setRestitution(double e);
    std::string setWallRestitution(double e);
    std::string setGravity(const std::array<double, 3>& g);

    // ---- staged until reset() ----
    std::string setSpeciesCount(size_t species, int64_t count);
    std::string setSpeciesMass(size_t species, double mass);
    std::string setSpeciesRadius(size_t species, double radius);
    std::string setBoxSize(const std::array<double, 3>& size);
    std::string setSeed(uint64_t seed);
    bool restartPending() const { return m_restartPending; }
    // Restarts from the pending scene (live settings included); returns "" or why it was refused
    // (e.g. more particles than fit), in which case nothing changes.
    std::string reset();
    // Replaces the whole scene (a preset): staged, then reset.
    std::string load(const Scene& scene);

    const Scene& live() const { return m_host.runningScene(); }
    const Scene& pending() const { return m_pending; }
    // Why the last edit was refused ("" after an applied one).
    const std::string& lastRefusal() const { return m_lastRefusal; }

private:
    // Validates `scene` (the running scene with one live edit) and pushes it; returns why not.
    std::string pushStepParameters(const Scene& scene);
    std::string applyThermostat(const ThermostatDef& thermostat);
    std::string refuse(const std::string& why);  // records and returns it
    std::string accept();                        // clears the record, returns ""

    SimulationHost& m_host;
    Scene m_pending;
    bool m_restartPending = false;
    std::string m_lastRefusal;
};

}  // namespace corebox
