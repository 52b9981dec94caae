#include "simulation.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <utility>

#include "collision_rounds.h"
#include "device_model.h"
#include "errors.h"
#include "scene_io.h"
#include "thermostat.h"

namespace corebox {

Simulation::Simulation(Scene scene, std::unique_ptr<Backend> backend, const ParticleState& initial, SimulationLimits limits)
    : m_scene(std::move(scene)), m_backend(std::move(backend)), m_limits(limits) {
    m_particleCount = int64_t(initial.size());
    m_countPerSpecies.assign(m_scene.species.size(), 0);
    for (int32_t s : initial.species) ++m_countPerSpecies[size_t(s)];
    m_backend->setState(initial);
    applyParameters();
    m_backend->keepSnapshot();
    const EnergySums e = m_backend->energies();
    double thermalT = m_scene.init.temperature;
    if (m_scene.thermostat.kind != ThermostatKind::None) thermalT = std::max(thermalT, m_scene.thermostat.temperature);
    m_energyScale = std::max({std::fabs(e.kinetic) + std::fabs(e.potential), 1.5 * double(m_particleCount) * thermalT, 1e-300});
    m_conserved0 = e.kinetic + e.potential;
    m_lastKinetic = e.kinetic;
    m_pressureGeometry = pressureGeometryOf(m_scene);
}

Simulation::Simulation(Scene scene, std::unique_ptr<Backend> backend, const SimulationCheckpoint& c, SimulationLimits limits)
    : m_scene(std::move(scene)), m_backend(std::move(backend)), m_limits(limits) {
    m_particleCount = int64_t(c.state.size());
    m_countPerSpecies.assign(m_scene.species.size(), 0);
    for (int32_t s : c.state.species) {
        if (s < 0 || size_t(s) >= m_countPerSpecies.size())
            throw InputError("checkpoint: species index " + std::to_string(s) + " but its scene defines " +
                             std::to_string(m_countPerSpecies.size()) + " species");
        ++m_countPerSpecies[size_t(s)];
    }
    m_backend->setState(c.state);
    applyParameters();
    m_driver.restoreNextDt(c.dtNext);
    m_backend->keepSnapshot();
    if (!c.accelerations.empty()) {
        if (c.accelerations.size() != c.state.size())
            throw InputError("checkpoint: " + std::to_string(c.accelerations.size()) + " cached accelerations for " +
                             std::to_string(c.state.size()) + " particles");
        m_backend->restoreAccelerations(c.accelerations);
        m_driver.restoreAccelerationsValid();
    }
    m_backend->restoreContactWarmStart(ContactCarryOver{c.contactImpulses, c.contactColours});
    m_step = c.step;
    m_time = c.time;
    m_dissipated = c.dissipated;
    m_thermostatEnergy = c.thermostatEnergy;
    m_parameterWork = c.parameterWork;
    m_conserved0 = c.conserved0;
    m_energyScale = c.energyScale;
    m_lastKinetic = c.lastKinetic;
    m_pairCollisions = c.pairCollisions;
    m_wallCollisions = c.wallCollisions;
    m_roundCapHits = c.roundCapHits;
    m_pressureWindow.restore(c.pressureTime, c.pressureKineticTime, c.pressureImpulses);
    m_pressureGeometry = pressureGeometryOf(m_scene);
}

SimulationCheckpoint Simulation::checkpoint() const {
    SimulationCheckpoint c;
    c.sceneToml = sceneToToml(m_scene);
    c.state = m_backend->state();
    c.step = m_step;
    c.time = m_time;
    c.dissipated = m_dissipated;
    c.thermostatEnergy = m_thermostatEnergy;
    c.parameterWork = m_parameterWork;
    c.conserved0 = m_conserved0;
    c.energyScale = m_energyScale;
    c.lastKinetic = m_lastKinetic;
    c.pairCollisions = m_pairCollisions;
    c.wallCollisions = m_wallCollisions;
    c.roundCapHits = m_roundCapHits;
    c.dtNext = m_driver.nextDt();
    if (m_driver.accelerationsValid()) c.accelerations = m_backend->cachedAccelerations();
    ContactCarryOver contacts = m_backend->contactWarmStart();
    c.contactImpulses = std::move(contacts.impulses);
    c.contactColours = std::move(contacts.colours);
    c.pressureTime = m_pressureWindow.time();
    c.pressureKineticTime = m_pressureWindow.kineticTime();
    c.pressureImpulses = m_pressureWindow.impulses();
    return c;
}

void Simulation::applyParameters() {
    if (m_scene.integrator.automatic)
        throw InputError("integrator: method = \"auto\" must be resolved (auto_integrator.h) before a simulation runs the scene");
    const StepParameters parameters = stepParametersOf(m_scene);
    m_forceChoice = chooseForceModel(parameters, m_particleCount, m_backend->name(), m_backend->supportsNeighbourLists());
    DeviceModel model = deviceModelOf(parameters);
    model.forces = m_forceChoice.model;
    m_smallestContact = model.smallestContact();
    m_backend->setModel(model);
    m_driver.configure(*m_backend, m_scene.integrator);
}

StepReport Simulation::step() {
    Backend& backend = *m_backend;
    backend.beginStep(m_step);
    backend.keepSnapshot();
    StepReport report;
    if (m_phaseTiming) backend.markPhase(StepPhase::Integrate);
    m_driver.integrate(backend, report);
    if (m_phaseTiming) backend.markPhase(StepPhase::Collide);
    resolveCollisions(backend, collisionSettingsFor(m_scene.interaction, report.dt, m_smallestContact), report);
    if (m_phaseTiming) backend.markPhase(StepPhase::Done);
    // Collisions moved some particles: Verlet's cached accelerations are stale for them and their
    // neighbours. A backend that can bring them up to date for just those keeps the cache; otherwise
    // the next step pays a full force pass.
    if (report.pairCollisions + report.wallCollisions + report.contacts > 0) {
        const bool cacheUsed = m_scene.integrator.method == Method::Verlet;
        if (!cacheUsed || !backend.refreshAccelerations()) m_driver.invalidateAccelerations();
    }

    ++m_step;
    m_time += report.dt;
    m_dissipated += report.dissipated;
    m_pairCollisions += report.pairCollisions;
    m_wallCollisions += report.wallCollisions;
    if (report.roundCapHit) ++m_roundCapHits;

    const ThermostatResult t = applyThermostat(*m_backend, m_scene.thermostat, report.dt, m_step, m_scene.init.seed, 3 * m_particleCount);
    m_thermostatEnergy += t.energyAdded();
    // Without a thermostat the kinetic energy and the health come back together (one host wait).
    StepCheck check;
    if (m_scene.thermostat.kind == ThermostatKind::None) {
        check = m_backend->checkStep();
    } else {
        check.kinetic = t.kineticAfter;
        check.health = m_backend->health();
    }
    const double kinetic = check.kinetic;
    const HealthReport& health = check.health;
    // Read after the check, whose wait has already covered the marked phases.
    if (m_phaseTiming) {
        const PhaseSeconds seconds = backend.phaseSeconds();
        report.secondsForces = seconds.forces;
        report.secondsIntegrate = seconds.integrate;
        report.secondsCollide = seconds.collide;
    }
    if (!health.ok()) {
        std::ostringstream detail;
        if (health.nonFinite > 0) detail << health.nonFinite << " particle(s) with non-finite position or velocity";
        if (health.outsideBox > 0) detail << (health.nonFinite > 0 ? ", " : "") << health.outsideBox << " particle(s) escaped the box";
        detail << " (e.g. particle";
        for (int64_t id : health.examples) detail << ' ' << id;
        detail << ')';
        fail("the state broke down", detail.str());
    }
    const double runawayBound = m_limits.runawayFactor * m_energyScale + std::fabs(m_thermostatEnergy) + std::fabs(m_conserved0);
    if (!std::isfinite(kinetic) || kinetic > runawayBound) {
        std::ostringstream detail;
        detail << "kinetic energy " << kinetic << " exceeds the runaway bound " << runawayBound << " (it was " << m_lastKinetic
               << " one step before)";
        fail("energy is growing without bound", detail.str());
    }
    m_lastKinetic = kinetic;
    m_pressureWindow.addStep(report, kinetic);
    return report;
}

ObservablesRow Simulation::observe() {
    const EnergySums e = m_backend->energies();
    ObservablesRow row;
    row.step = m_step;
    row.time = m_time;
    row.kinetic = e.kinetic;
    row.potential = e.potential;
    row.dissipated = m_dissipated;
    row.thermostat = m_thermostatEnergy;
    row.px = e.momentum.x;
    row.py = e.momentum.y;
    row.pz = e.momentum.z;
    row.temperature = m_particleCount > 0 ? 2.0 * e.kinetic / (3.0 * double(m_particleCount)) : 0.0;
    row.forces = m_forceChoice.model;
    row.collisionsPair = m_pairCollisions;
    row.collisionsWall = m_wallCollisions;
    for (size_t s = 0; s < m_countPerSpecies.size(); ++s) {
        row.speciesTemperature.push_back(m_countPerSpecies[s] > 0 ? 2.0 * e.kineticPerSpecies[s] / (3.0 * double(m_countPerSpecies[s])) : 0.0);
    }
    m_pairCollisions = 0;
    m_wallCollisions = 0;
    row.window = m_pressureWindow.time();
    row.impulses = m_pressureWindow.impulses();
    row.pressureWall = m_pressureWindow.wallPressure(m_pressureGeometry);
    row.pressureWallCentre = m_pressureWindow.wallCentrePressure(m_pressureGeometry);
    row.pressureVirial = row.window > 0 ? m_pressureWindow.virialPressure(m_pressureGeometry, m_backend->pairVirial()) : 0.0;
    m_pressureWindow.reset();
    if (!std::isfinite(row.conserved())) fail("the energy is not finite", "E_kin = " + std::to_string(e.kinetic) + ", E_pot = " + std::to_string(e.potential));
    const double drift = std::fabs(row.conserved() - m_conserved0);
    if (drift > m_limits.maxEnergyDrift * m_energyScale) {
        std::ostringstream detail;
        detail << "the conserved energy E_kin + E_pot + E_diss - E_thermo moved by " << drift << ", more than "
               << m_limits.maxEnergyDrift << " of the energy scale " << m_energyScale;
        fail("energy drift beyond the bound", detail.str());
    }
    return row;
}

void Simulation::setStepParameters(const StepParameters& parameters) {
    // An edit of the potential (gravity, mixing, cutoff) changes E_pot of the same state: that is work
    // done on the system, not integration error. It is measured (a force pass before and after) and the
    // conserved sum re-based by it, so the drift check keeps watching the integration alone.
    const InteractionDef& was = m_scene.interaction;
    const InteractionDef& next = parameters.interaction;
    bool accelerationEdited = false;
    for (size_t s = 0; s < m_scene.species.size() && s < parameters.species.size(); ++s) {
        accelerationEdited = accelerationEdited || m_scene.species[s].acceleration != parameters.species[s].acceleration;
    }
    const bool potentialEdited = was.gravity != next.gravity || was.mixing != next.mixing || was.cutoff != next.cutoff ||
                                 was.shift != next.shift || accelerationEdited;
    const double before = potentialEdited ? m_backend->energies().potential : 0.0;
    m_scene.integrator = parameters.integrator;
    m_scene.interaction = parameters.interaction;
    m_scene.box.wallRestitution = parameters.box.wallRestitution;
    for (size_t s = 0; s < m_scene.species.size() && s < parameters.species.size(); ++s) {
        m_scene.species[s].acceleration = parameters.species[s].acceleration;
    }
    applyParameters();
    if (!potentialEdited) return;
    const EnergySums after = m_backend->energies();
    const double work = after.potential - before;  // the kinetic energy is the same state's
    m_conserved0 += work;
    m_parameterWork += work;
    m_energyScale = std::max(m_energyScale, std::fabs(after.kinetic) + std::fabs(after.potential));
}

double Simulation::replaceParticles(std::vector<SpeciesDef> species, const ParticleState& state) {
    std::vector<int64_t> counts(species.size(), 0);
    for (int32_t s : state.species) {
        if (s < 0 || size_t(s) >= counts.size())
            throw InputError("particle of species " + std::to_string(s) + " but the world has " + std::to_string(counts.size()) +
                             " species");
        ++counts[size_t(s)];
    }
    const EnergySums before = m_backend->energies();
    for (size_t s = 0; s < species.size(); ++s) species[s].count = counts[s];
    m_scene.species = std::move(species);
    m_countPerSpecies = std::move(counts);
    m_particleCount = int64_t(state.size());
    m_backend->setState(state);
    applyParameters();
    m_driver.invalidateAccelerations();
    m_backend->keepSnapshot();
    const EnergySums after = m_backend->energies();
    const double work = (after.kinetic + after.potential) - (before.kinetic + before.potential);
    m_conserved0 += work;
    m_parameterWork += work;
    m_energyScale = std::max(m_energyScale, std::fabs(after.kinetic) + std::fabs(after.potential));
    m_lastKinetic = after.kinetic;
    return work;
}

void Simulation::setThermostat(const ThermostatDef& thermostat) { m_scene.thermostat = thermostat; }

void Simulation::replaceBackend(std::unique_ptr<Backend> backend) {
    const ParticleState current = m_backend->state();
    m_backend = std::move(backend);
    m_backend->setState(current);
    applyParameters();
    m_backend->keepSnapshot();
}

SpeedStatistics Simulation::speedStatistics(const SpeedRequest& request) const {
    return speedStatisticsOf(m_backend->state(), m_scene.species, request);
}

std::string Simulation::likelyCause() const {
    const Method m = m_scene.integrator.method;
    std::ostringstream out;
    if (m_scene.integrator.adaptive) {
        out << "likely cause: adaptive " << methodName(m) << " (tolerance " << m_scene.integrator.tolerance << ") had grown its step to "
            << m_driver.nextDt() << " (at most " << kAdaptiveGrowthCap << " x dt = " << kAdaptiveGrowthCap * m_scene.integrator.dt
            << "): its error estimate sees the smooth forces only, not collisions or walls; tighten the tolerance or lower dt";
        return out.str();
    }
    out << "likely cause: dt = " << m_scene.integrator.dt << " is too large for " << methodName(m) << " ("
        << precisionName(m_scene.integrator.precision) << ")";
    switch (m) {
        case Method::Euler:
        case Method::Rk2: out << "; euler and rk2 gain energy on every oscillation at any dt: prefer verlet or rk4"; break;
        case Method::Rk4: out << "; rk4 is stable up to omega*dt ~ 2.83 for the fastest oscillation"; break;
        case Method::Verlet: out << "; verlet is stable up to omega*dt = 2 for the fastest oscillation"; break;
        case Method::ForestRuth:
        case Method::Pefrl:
        case Method::BlanesMoan:
        case Method::Yoshida6:
        case Method::Yoshida8:
            out << "; " << methodName(m) << " is stable up to omega*dt ~ " << compositionStabilityLimit(m)
                << " for the fastest oscillation (linear theory)";
            break;
        case Method::Dp5: out << "; dp5 is stable up to omega*dt ~ 1.0 (or use adaptive = true)"; break;
        case Method::Hairer10: out << "; hairer10 is stable up to omega*dt ~ 1.16"; break;
    }
    out << ", or particles start too close (strong LJ repulsion)";
    return out.str();
}

void Simulation::fail(const std::string& what, const std::string& detail) const {
    throw InstabilityError("instability at step " + std::to_string(m_step) + " (t = " + std::to_string(m_time) + "): " + what +
                           ": " + detail + "; " + likelyCause());
}

}  // namespace corebox
