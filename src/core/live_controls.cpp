#include "live_controls.h"

#include <stdexcept>

#include "errors.h"

namespace corebox {

LiveControls::LiveControls(SimulationHost& host) : m_host(host), m_pending(host.runningScene()) {}

void LiveControls::pushStepParameters(const Scene& scene) {
    m_host.applyStepParameters(stepParametersOf(scene));
    // Keep the staged scene's live part in step, so a later reset keeps the live edits.
    m_pending.integrator = scene.integrator;
    m_pending.interaction = scene.interaction;
    m_pending.box.wallRestitution = scene.box.wallRestitution;
}

void LiveControls::setTargetTemperature(double kT) {
    if (!(kT > 0)) return;
    ThermostatDef t = live().thermostat;
    t.temperature = kT;
    m_host.applyThermostat(t);
    m_pending.thermostat = t;
}

void LiveControls::setThermostatKind(ThermostatKind kind) {
    ThermostatDef t = live().thermostat;
    t.kind = kind;
    m_host.applyThermostat(t);
    m_pending.thermostat = t;
}

void LiveControls::setThermostatTau(double tau) {
    if (!(tau > 0)) return;
    ThermostatDef t = live().thermostat;
    t.tau = tau;
    m_host.applyThermostat(t);
    m_pending.thermostat = t;
}

void LiveControls::setMixing(size_t i, size_t j, double x) {
    Scene s = live();
    const size_t n = s.species.size();
    if (i >= n || j >= n || x < 0) return;
    if (s.interaction.mixing.empty()) s.interaction.mixing.assign(n, std::vector<double>(n, 1.0));
    s.interaction.mixing[i][j] = x;
    s.interaction.mixing[j][i] = x;
    pushStepParameters(s);
}

void LiveControls::setLikeUnlikeMixing(double like, double unlike) {
    Scene s = live();
    const size_t n = s.species.size();
    if (like < 0 || unlike < 0) return;
    s.interaction.mixing.assign(n, std::vector<double>(n, unlike));
    for (size_t i = 0; i < n; ++i) s.interaction.mixing[i][i] = like;
    pushStepParameters(s);
}

void LiveControls::setMethod(Method method) {
    Scene s = live();
    s.integrator.method = method;
    if (method != Method::Dp5) s.integrator.adaptive = false;
    pushStepParameters(s);
}

void LiveControls::setDt(double dt) {
    if (!(dt > 0)) return;
    Scene s = live();
    s.integrator.dt = dt;
    pushStepParameters(s);
}

void LiveControls::setPrecision(Precision precision) {
    if (precision == live().integrator.precision) return;
    m_host.switchPrecision(precision);
    m_pending.integrator.precision = precision;
}

void LiveControls::setRestitution(double e) {
    if (e < 0 || e > 1) return;
    Scene s = live();
    s.interaction.restitution = e;
    pushStepParameters(s);
}

void LiveControls::setWallRestitution(double e) {
    if (e < 0 || e > 1) return;
    Scene s = live();
    s.box.wallRestitution = e;
    pushStepParameters(s);
}

void LiveControls::setGravity(const std::array<double, 3>& g) {
    Scene s = live();
    s.interaction.gravity = g;
    pushStepParameters(s);
}

void LiveControls::setSpeciesCount(size_t species, int64_t count) {
    if (species >= m_pending.species.size() || count < 0) return;
    m_pending.species[species].count = count;
    m_restartPending = true;
}

void LiveControls::setSpeciesMass(size_t species, double mass) {
    if (species >= m_pending.species.size() || !(mass > 0)) return;
    m_pending.species[species].mass = mass;
    m_restartPending = true;
}

void LiveControls::setSpeciesRadius(size_t species, double radius) {
    if (species >= m_pending.species.size() || !(radius > 0)) return;
    m_pending.species[species].radius = radius;
    m_restartPending = true;
}

void LiveControls::setBoxSize(const std::array<double, 3>& size) {
    if (!(size[0] > 0 && size[1] > 0 && size[2] > 0)) return;
    m_pending.box.size = size;
    m_restartPending = true;
}

void LiveControls::setSeed(uint64_t seed) {
    m_pending.init.seed = seed;
    m_restartPending = true;
}

std::string LiveControls::reset() {
    try {
        m_host.restart(m_pending);
    } catch (const InputError& e) {
        return e.what();
    }
    m_pending = m_host.runningScene();
    m_restartPending = false;
    return "";
}

std::string LiveControls::load(const Scene& scene) {
    const Scene previous = m_pending;
    m_pending = scene;
    const std::string error = reset();
    if (!error.empty()) m_pending = previous;
    return error;
}

}  // namespace corebox
