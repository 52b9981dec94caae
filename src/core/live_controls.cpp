#include "live_controls.h"

#include <cmath>
#include <stdexcept>

#include "errors.h"
#include "scene_validation.h"

namespace corebox {

LiveControls::LiveControls(SimulationHost& host) : m_host(host), m_pending(host.runningScene()) {}

namespace {

// The first rule of scene validation that `scene` breaks, or "".
std::string validationProblem(const Scene& scene) {
    try {
        validateScene(scene, SceneLocations("live edit"));
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

std::string finitePositive(const char* key, double value) {
    if (std::isfinite(value) && value > 0) return "";
    return std::string(key) + ": must be a finite number > 0 (got " + std::to_string(value) + ")";
}

}  // namespace

std::string LiveControls::refuse(const std::string& why) {
    m_lastRefusal = why;
    return why;
}

std::string LiveControls::accept() {
    m_lastRefusal.clear();
    return "";
}

std::string LiveControls::pushStepParameters(const Scene& scene) {
    const std::string problem = validationProblem(scene);
    if (!problem.empty()) return refuse(problem);
    m_host.applyStepParameters(stepParametersOf(scene));
    // Keep the staged scene's live part in step, so a later reset keeps the live edits.
    m_pending.integrator = scene.integrator;
    m_pending.interaction = scene.interaction;
    m_pending.box.wallRestitution = scene.box.wallRestitution;
    return accept();
}

std::string LiveControls::applyThermostat(const ThermostatDef& thermostat) {
    Scene s = live();
    s.thermostat = thermostat;
    const std::string problem = validationProblem(s);
    if (!problem.empty()) return refuse(problem);
    m_host.applyThermostat(thermostat);
    m_pending.thermostat = thermostat;
    return accept();
}

std::string LiveControls::setTargetTemperature(double kT) {
    ThermostatDef t = live().thermostat;
    t.temperature = kT;
    return applyThermostat(t);
}

std::string LiveControls::setThermostatKind(ThermostatKind kind) {
    ThermostatDef t = live().thermostat;
    t.kind = kind;
    return applyThermostat(t);
}

std::string LiveControls::setThermostatTau(double tau) {
    ThermostatDef t = live().thermostat;
    t.tau = tau;
    return applyThermostat(t);
}

std::string LiveControls::setMixing(size_t i, size_t j, double x) {
    Scene s = live();
    const size_t n = s.species.size();
    if (i >= n || j >= n) {
        return refuse("interaction.mixing: species index " + std::to_string(i >= n ? i : j) + " out of range (the scene has " +
                      std::to_string(n) + " species, indices 0 to " + std::to_string(n - 1) + ")");
    }
    if (s.interaction.mixing.empty()) s.interaction.mixing.assign(n, std::vector<double>(n, 1.0));
    s.interaction.mixing[i][j] = x;
    s.interaction.mixing[j][i] = x;
    return pushStepParameters(s);
}

std::string LiveControls::setLikeUnlikeMixing(double like, double unlike) {
    Scene s = live();
    const size_t n = s.species.size();
    s.interaction.mixing.assign(n, std::vector<double>(n, unlike));
    for (size_t i = 0; i < n; ++i) s.interaction.mixing[i][i] = like;
    return pushStepParameters(s);
}

std::string LiveControls::setMethod(Method method) {
    Scene s = live();
    s.integrator.method = method;
    if (method != Method::Dp5) s.integrator.adaptive = false;
    return pushStepParameters(s);
}

std::string LiveControls::setDt(double dt) {
    Scene s = live();
    s.integrator.dt = dt;
    return pushStepParameters(s);
}

std::string LiveControls::setPrecision(Precision precision) {
    if (precision == live().integrator.precision) return accept();
    Scene s = live();
    s.integrator.precision = precision;  // fp32 has narrower bounds on the scales (scene_validation)
    const std::string problem = validationProblem(s);
    if (!problem.empty()) return refuse(problem);
    m_host.switchPrecision(precision);
    m_pending.integrator.precision = precision;
    return accept();
}

std::string LiveControls::setRestitution(double e) {
    Scene s = live();
    s.interaction.restitution = e;
    return pushStepParameters(s);
}

std::string LiveControls::setWallRestitution(double e) {
    Scene s = live();
    s.box.wallRestitution = e;
    return pushStepParameters(s);
}

std::string LiveControls::setGravity(const std::array<double, 3>& g) {
    Scene s = live();
    s.interaction.gravity = g;
    return pushStepParameters(s);
}

std::string LiveControls::setSpeciesCount(size_t species, int64_t count) {
    if (species >= m_pending.species.size()) return refuse("species index " + std::to_string(species) + " out of range");
    if (count < 0) return refuse("species[" + std::to_string(species) + "].count: must be >= 0 (got " + std::to_string(count) + ")");
    m_pending.species[species].count = count;
    m_restartPending = true;
    return accept();
}

std::string LiveControls::setSpeciesMass(size_t species, double mass) {
    if (species >= m_pending.species.size()) return refuse("species index " + std::to_string(species) + " out of range");
    const std::string problem = finitePositive("species.mass", mass);
    if (!problem.empty()) return refuse(problem);
    m_pending.species[species].mass = mass;
    m_restartPending = true;
    return accept();
}

std::string LiveControls::setSpeciesRadius(size_t species, double radius) {
    if (species >= m_pending.species.size()) return refuse("species index " + std::to_string(species) + " out of range");
    const std::string problem = finitePositive("species.radius", radius);
    if (!problem.empty()) return refuse(problem);
    m_pending.species[species].radius = radius;
    m_restartPending = true;
    return accept();
}

std::string LiveControls::setBoxSize(const std::array<double, 3>& size) {
    for (double l : size) {
        const std::string problem = finitePositive("box.size", l);
        if (!problem.empty()) return refuse(problem);
    }
    m_pending.box.size = size;
    m_restartPending = true;
    return accept();
}

std::string LiveControls::setSeed(uint64_t seed) {
    m_pending.init.seed = seed;
    m_restartPending = true;
    return accept();
}

std::string LiveControls::reset() {
    const std::string problem = validationProblem(m_pending);
    if (!problem.empty()) return refuse(problem);
    try {
        m_host.restart(m_pending);
    } catch (const InputError& e) {
        return refuse(e.what());
    }
    m_pending = m_host.runningScene();
    m_restartPending = false;
    return accept();
}

std::string LiveControls::load(const Scene& scene) {
    const Scene previous = m_pending;
    m_pending = scene;
    const std::string error = reset();
    if (!error.empty()) m_pending = previous;
    return error;
}

}  // namespace corebox
