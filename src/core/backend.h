// The backend interface: what the simulation core asks of a compute device. The CPU backend
// (src/cpu) is the reference; the CUDA backend (src/cuda) implements the same contract and is
// tested against it. The core never sees how or where the work runs.
//
// One step = integrate the equations of motion by dt (forces + RK stages or Verlet), then resolve
// hard-core and wall collisions a posteriori (DESIGN.md sec. 2). Thermostat and blow-up policy live
// in the core (src/core/simulation.*); a backend only scales velocities and reports sums, so only
// small results cross from a device to the host.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "particle_state.h"
#include "scene.h"

namespace corebox {

struct StepReport {
    double dt = 0;                 // the step actually taken (adaptive dp5 may shrink it)
    int rejectedSteps = 0;         // adaptive attempts rejected before this one
    int64_t pairCollisions = 0;    // particle-particle impulses applied
    int64_t wallCollisions = 0;    // wall reflections applied
    int64_t positionalFixes = 0;   // overlaps separated without an impulse (not approaching)
    double dissipated = 0;         // kinetic energy lost in inelastic collisions this step [eps]
    int rounds = 0;                // parallel resolution rounds used
    bool roundCapHit = false;      // overlaps remained after InteractionDef::maxCollisionRounds
    // Where the step's time went [s]: force passes, the rest of the integration, collisions.
    double secondsForces = 0, secondsIntegrate = 0, secondsCollide = 0;
};

struct EnergySums {
    double kinetic = 0;
    double potential = 0;  // pair + gravitational (-m g.x)
    Vec3<double> momentum{0, 0, 0};
    std::vector<double> kineticPerSpecies;
};

// Particles that broke a physical invariant; the first few indices are kept for the message.
struct HealthReport {
    int64_t nonFinite = 0;
    int64_t outsideBox = 0;
    std::vector<int64_t> examples;
    bool ok() const { return nonFinite == 0 && outsideBox == 0; }
};

struct SpeedStatistics {
    int species = -1;                // -1: all particles
    int64_t count = 0;
    std::vector<int64_t> histogram;  // counts per bin over [0, maxSpeed)
    double maxSpeed = 0;
    double ksStatistic = 0;          // Kolmogorov-Smirnov D against MB at the given temperature
};

struct SpeedRequest {
    int species = -1;
    int bins = 40;
    double maxSpeed = 4.0;
    double temperature = 1.0;  // MB reference temperature; the masses come from the species table
};

class Backend {
public:
    virtual ~Backend() = default;

    virtual std::string name() const = 0;
    virtual std::string deviceName() const = 0;  // "NVIDIA H200 (...)", the CPU model, for records
    virtual Precision precision() const = 0;

    virtual void setParameters(const StepParameters& parameters) = 0;
    virtual void setState(const ParticleState& state) = 0;
    virtual ParticleState state() const = 0;

    virtual StepReport step() = 0;

    virtual double kineticEnergy() = 0;            // O(N)
    virtual void scaleVelocities(double alpha) = 0;
    virtual EnergySums energies() = 0;             // includes the O(N^2) potential
    virtual HealthReport health() = 0;             // O(N)
    virtual SpeedStatistics speedStatistics(const SpeedRequest& request) = 0;

    // Snapshot of the current state kept beside the live one (on the device for GPU backends), so
    // the last good state survives a blow-up without a download every step.
    virtual void keepSnapshot() = 0;
    virtual ParticleState snapshot() const = 0;

    // Force pass alone, for benchmarks: returns the pair interactions evaluated.
    virtual int64_t computeForcesOnly() = 0;
};

}  // namespace corebox
