// LiveControls: the edits a running simulation accepts (from the panel, a script or a test) and when
// each takes effect. Core code with no ImGui or GL, so it is unit-tested and the panel stays a view.
//
// Live settings (temperature and thermostat, mixing x_ij, integrator and dt, precision, restitution,
// gravity) reach the running simulation at once through the SimulationHost. Creation-time settings
// (counts, masses, radii, box, seed) are staged in a pending scene and only applied by reset(), which
// restarts the run from that scene.
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
    void setTargetTemperature(double kT);
    void setThermostatKind(ThermostatKind kind);  // None switches it off
    void setThermostatTau(double tau);
    void setMixing(size_t i, size_t j, double x);  // symmetric: sets x_ij and x_ji
    void setLikeUnlikeMixing(double like, double unlike);
    void setMethod(Method method);
    void setDt(double dt);
    void setPrecision(Precision precision);
    void setRestitution(double e);
    void setWallRestitution(double e);
    void setGravity(const std::array<double, 3>& g);

    // ---- staged until reset() ----
    void setSpeciesCount(size_t species, int64_t count);
    void setSpeciesMass(size_t species, double mass);
    void setSpeciesRadius(size_t species, double radius);
    void setBoxSize(const std::array<double, 3>& size);
    void setSeed(uint64_t seed);
    bool restartPending() const { return m_restartPending; }
    // Restarts from the pending scene (live settings included); returns "" or why it was refused
    // (e.g. more particles than fit), in which case nothing changes.
    std::string reset();
    // Replaces the whole scene (a preset): staged, then reset.
    std::string load(const Scene& scene);

    const Scene& live() const { return m_host.runningScene(); }
    const Scene& pending() const { return m_pending; }

private:
    void pushStepParameters(const Scene& scene);

    SimulationHost& m_host;
    Scene m_pending;
    bool m_restartPending = false;
};

}  // namespace corebox
