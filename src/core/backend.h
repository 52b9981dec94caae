// The device interface: the few operations the core's step orchestration asks of a compute device
// (DESIGN.md sec. 1). The orchestration itself (integration driver, collision rounds, thermostat,
// health policy: src/core/integration_driver.*, collision_rounds.*, simulation.*) is written once
// against this interface; the CPU backend (src/cpu) implements it as the reference and the CUDA
// backend (src/cuda) on a GPU. A backend spanning several devices implements the same calls over its
// partition (each call may fan out to every device and gather what the next call needs); the
// orchestration never learns how many devices there are.
//
// What a backend holds, by role (names used in the comments below):
//   X, V       the state: positions and velocities, one row per particle, in the backend's precision;
//   A          cached accelerations a(X) (velocity Verlet);
//   Xs, Vs     stage state of a Runge-Kutta step (and its solution before acceptance);
//   Kx_s, Kv_s stage derivatives (velocity and acceleration of stage s), as many as the tableau has;
//   snapshot   a copy of (X, V) kept beside the state so the last good state survives a blow-up;
//   events     each particle's earliest collision event of the current round, its active flag, the
//              accumulated collision counts, dissipated energy and impulses of the step.
// Calls are ordered: a backend may queue work asynchronously, but every call that returns a value to
// the host (findEvents, the reductions, state downloads) sees the effects of every earlier call.
// Only small results cross from a device to the host, except state() and snapshot().
//
// Not here on purpose: benchmarks (they time computeAccelerations + finish), speed histograms and
// Kolmogorov-Smirnov statistics (computed by the core from state(), see speed_statistics.h).
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "butcher_tableau.h"
#include "corebox/device_state.h"  // DeviceState: shared with the public API
#include "collision_resolution.h"
#include "contact_relaxation.h"
#include "device_model.h"
#include "impulse_sums.h"
#include "particle_instance.h"
#include "particle_state.h"
#include "scene.h"
#include "step_report.h"  // StageScreen

namespace corebox {

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

// What the impact rounds of one step did, summed over particles.
// Force work done since the backend was made, for tests and benchmarks: full passes (every
// particle's acceleration, or an RK stage's), partial refreshes after collisions, neighbour-list
// builds.
struct ForceCounters {
    int64_t fullPasses = 0;
    int64_t refreshes = 0;
    int64_t refreshedParticles = 0;  // accelerations recomputed by the refreshes
    int64_t listBuilds = 0;
    int64_t allPairsEvaluations = 0;  // pair evaluations of the all-pairs full passes (ordered pairs, or each pair once)
    int64_t stepsRunAhead = 0;        // steps whose kick-drift and force pass ran before the host asked (CUDA)
};

// What runImpactRounds did: the rounds run, and whether the last found no event.
struct ImpactRounds {
    int rounds = 0;
    bool settled = false;
};

struct CollisionTally {
    int64_t pairCollisions = 0;   // particle-particle impulses applied
    int64_t wallCollisions = 0;   // wall reflections applied
    double dissipated = 0;        // kinetic energy lost in inelastic collisions [eps]
    ImpulseSums impulses;         // given to the walls and r_ij . J_ij of the pairs (pressure.h)
    int64_t total() const { return pairCollisions + wallCollisions; }
};

// One impact resolved by the impact rounds of the last step (collision_resolution.h ImpactDetail), in
// particle indices. Every pair and wall collision counted by the tally has one record. Contacts held by
// the contact relaxation (resting, slow) are not impacts and have none.
struct ContactRecord {
    int64_t a = 0;             // the particle (of a pair, the lower index)
    int64_t b = 0;             // the partner's index, or a wall code -1 - (2 axis + side)
    int32_t round = 0;         // the impact round of the step (events of one round touch distinct particles)
    double time = 0;           // when within the step, 0 .. dt [tau]
    Vec3<double> normal{0, 0, 0};  // unit, from b to a; for a wall, into the box
    double impulse = 0;        // normal impulse given to a (b receives its opposite) [m sigma / tau]
    double speed = 0;          // normal approach speed at contact [sigma / tau]
};

// Where a backend hands its positions (readPositions: first index, values, count), a chunk at a time,
// possibly from several threads at once for disjoint chunks (state_conversions.h), inside a parallel
// region: a sink must not throw.
using PositionSink = std::function<void(size_t first, const Vec3<double>* x, size_t count)>;

// What a step's contact phase leaves the next one: the impulses its relaxation ended with, which
// warm-start the next step's (contact_relaxation.h), and, from a backend that keeps its contacts'
// Gauss-Seidel colours from step to step (the CUDA backend, between fresh colourings), each record's
// colour in its listing, one a record (empty from others).
struct ContactCarryOver {
    std::vector<ContactWarmStart> impulses;
    std::vector<uint8_t> colours;
};

// The end-of-step check without a thermostat: the kinetic energy and the health report together (a
// GPU reads both back at once).
struct StepCheck {
    double kinetic = 0;
    HealthReport health;
};

// Which particles look for events in a round: the active ones (those with an event in the previous
// round; in a stage's first round those fast enough for an impact, collision_resolution.h startsActive)
// against all neighbours, the others only against active neighbours; or every particle against every
// neighbour (the final check after the cap).
enum class EventScope { Active, All };

// Phases of a step, marked by the orchestration so that a backend can time them its own way (host
// clock on the CPU, stream events on a GPU) without a host wait inside the step.
enum class StepPhase { Integrate, Collide, Done };
struct PhaseSeconds {
    double forces = 0;     // force passes of the integration
    double integrate = 0;  // the rest of the integration
    double collide = 0;    // collision rounds
};

// Where writeInstances puts the renderer's instances: host memory, or device memory of the backend's
// interopDevice() (a mapped GL buffer). n = the particle count entries.
struct InstanceTarget {
    enum class Memory { Host, Device };
    Memory memory = Memory::Host;
    ParticleInstance* instances = nullptr;
    InstanceKey key = InstanceKey::Species;
};

class Backend {
public:
    virtual ~Backend() = default;

    // ---- identity ----
    virtual std::string name() const = 0;        // "cpu", "cuda"
    virtual std::string deviceName() const = 0;  // "NVIDIA H200 (...)", the CPU model, for records
    virtual Precision precision() const = 0;
    // The CUDA device whose memory writeInstances can fill directly (interop), or -1: host only.
    virtual int interopDevice() const { return -1; }
    // The state on the GPU after the last step (with several GPUs: the home GPU's gathered copy).
    virtual DeviceState deviceState() { return DeviceState{}; }
    // Makes the calling thread ready to drive this backend: a CUDA backend makes its home GPU the
    // thread's current device (CUDA keeps the current device per thread, and a new thread starts on
    // device 0). Callers that may change threads between calls (the library's World) call it first.
    virtual void bindCallingThread() {}

    // ---- model and state ----
    virtual void setModel(const DeviceModel& model) = 0;         // per-species tables, box, gravity, restitution
    virtual void setTableau(const ButcherTableau& tableau) = 0;  // weights for rkStage / rkSolution / rkErrorNorm
    virtual void setState(const ParticleState& state) = 0;
    virtual ParticleState state() const = 0;
    // state() into `out`, reusing its memory: for readers that take the state every frame (the
    // library's host mirror), where fresh vectors cost their page faults and a pageable download its
    // staging.
    virtual void readState(ParticleState& out) const { out = state(); }
    // The positions alone, handed to `sink` a chunk at a time (first index, values, count; PositionSink):
    // a reader that only draws downloads half of readState's bytes and converts a third of its
    // values, and converts them into its own memory from a chunk still in cache, with no full-length copy
    // between (the World's mirror). A backend holding doubles hands its own array at once.
    virtual void readPositions(const PositionSink& sink) const = 0;
    virtual void keepSnapshot() = 0;  // snapshot = (X, V), on the device
    virtual ParticleState snapshot() const = 0;

    // ---- integration ----
    virtual void computeAccelerations() = 0;  // A = a(X)
    virtual void kick(double h) = 0;          // V += h A
    virtual void drift(double dt) = 0;        // X += dt V
    // kick(h) then drift(dt), and computeAccelerations() then kick(h): the same arithmetic, in one pass
    // over the particles where a backend fuses them (a GPU launch each, not two).
    virtual void kickDrift(double h, double dt) {
        kick(h);
        drift(dt);
    }
    virtual void accelerateAndKick(double h) {
        computeAccelerations();
        kick(h);
    }
    // Stage s of an explicit RK step from (X, V): (Xs, Vs) = y0 + dt sum_{j<s} a_sj K_j, Kx_s = Vs.
    virtual void rkStage(int stage, double dt) = 0;
    virtual void stageForces(int stage) = 0;  // Kv_s = a(Xs)
    // (Xs, Vs) = y0 + dt sum_{j<stages} b_j K_j: the step's solution, not yet accepted.
    virtual void rkSolution(int stages, double dt) = 0;
    // A whole explicit RK step up to its solution: each stage and its forces, then rkSolution. A
    // backend may run it as one piece of work (the CUDA backend: one graph launch at small N).
    virtual void rkStep(int stages, double dt) {
        for (int s = 0; s < stages; ++s) {
            rkStage(s, dt);
            stageForces(s);
        }
        rkSolution(stages, dt);
    }
    // Root mean square over the 6N components of the scaled error of the embedded pair after
    // rkSolution (rk_stage.h: scaledErrorSquared); <= 1 means within tolerance.
    virtual double rkErrorNorm(double dt, double tolerance) = 0;
    virtual void acceptStage() = 0;  // (X, V) = (Xs, Vs)
    // After the collision stage moved some particles: brings A = a(X) up to date for those particles
    // and every particle they interact with, at a cost of the moved particles times their partners
    // rather than a full pass. Returns false when A was not valid for the positions before the
    // collision stage (or the backend cannot do it): then the caller recomputes A.
    virtual bool refreshAccelerations() { return false; }
    // The cached A (checkpoints) when it may differ from a force pass at X in the last bits (an
    // incremental refresh); empty when a force pass reproduces it. restoreAccelerations sets it.
    virtual std::vector<Vec3<double>> cachedAccelerations() const { return {}; }
    virtual void restoreAccelerations(const std::vector<Vec3<double>>& /*a*/) {}
    virtual ForceCounters forceCounters() const { return ForceCounters{}; }
    // Whether the backend sums forces from neighbour lists when the model asks for them
    // (DeviceModel::forces); one that does not runs all pairs, and the force choice says so.
    virtual bool supportsNeighbourLists() const { return false; }

    // ---- a posteriori collision stage, 0: the screen ----
    // What the backend knows, from the last force pass at the current positions, of the stage to come
    // (StageScreen), with `contactGap` the resting gap of the contact phase. Quiet: the stage is
    // skipped, and the backend leaves itself as an empty stage would (no contact log, no warm start).
    // WallsOnly: no pair can meet in this stage; the stage runs with resolveWallImpacts (or rounds that
    // search walls alone). Full (the default: a
    // backend that cannot tell): the whole stage. One host wait instead of the stage's searches.
    // `window` is the one the stage's beginCollisions will be given: a backend may resolve an easy stage
    // (and queue the end-of-step check) within the screen's wait, and the calls that follow then return
    // what it found.
    virtual StageScreen screenStage(const ImpactWindow<double>& /*window*/, double /*contactGap*/) { return StageScreen::Full; }
    // ---- a posteriori collision stage, 1: impact rounds (DESIGN.md sec. 2) ----
    // The first round's active particles those fast enough for an impact (startsActive: the same events as
    // every particle active); counts and losses zeroed. The window says which overlaps are impacts of
    // this step (collision_resolution.h).
    virtual void beginCollisions(const ImpactWindow<double>& window) = 0;
    // After screenStage said WallsOnly and beginCollisions: resolves every wall impact of the stage at
    // once, each particle's in the order the rounds would take them (particles that cannot meet each
    // other have independent sequences: the rounds' result exactly), and returns the rounds the loop
    // would have counted (the most impacts of one particle, plus the round that finds none). -1 when
    // the backend does not (the rounds run).
    virtual int resolveWallImpacts() { return -1; }
    // Each particle's earliest event (collision_resolution.h); returns how many particles have one.
    virtual int64_t findEvents(EventScope scope) = 0;
    // Resolves every event that is the earliest of each particle it touches (a matching, so no two
    // resolutions write one particle), then marks the particles that had an event as active.
    virtual void applyEvents() = 0;
    // Rounds of findEvents(Active) and applyEvents until a round finds no event (it counts) or maxRounds
    // ran. The default runs them from here, a read-back a round; a backend may queue several rounds and
    // read their counts once (the CUDA backend, where no pair force makes a round's accelerations
    // depend on what the last one found), with the same result.
    virtual ImpactRounds runImpactRounds(int maxRounds) {
        ImpactRounds r;
        while (r.rounds < maxRounds && !r.settled) {
            ++r.rounds;
            r.settled = findEvents(EventScope::Active) == 0;
            if (!r.settled) applyEvents();
        }
        return r;
    }
    virtual CollisionTally collisionTally() = 0;  // since beginCollisions
    // The contact log: when on, applyEvents records every impact it resolves and beginCollisions
    // clears the record; contactLog() returns the step's records ordered by (round, a), the same on
    // every backend. Off by default (it costs a record per impact). `minImpulse`: only impacts whose
    // impulse magnitude is at least this are recorded [m sigma / tau], compared in double; the others
    // cost no record, no copy and no sort (a game that flashes or plays sounds only above a threshold).
    // Backends agree on the impulses to rounding, so an impact within rounding of the threshold may be
    // recorded by one and not another.
    virtual void setContactLog(bool on, double minImpulse) = 0;
    // The log into `out`, reusing its memory (a game reads it every step).
    virtual void readContactLog(std::vector<ContactRecord>& out) const = 0;
    std::vector<ContactRecord> contactLog() const {
        std::vector<ContactRecord> out;
        readContactLog(out);
        return out;
    }

    // ---- collision stage, 2: contact relaxation (contact_relaxation.h) ----
    // Whether the backend sweeps the current listing Gauss-Seidel (contact_relaxation.h): a
    // warm-started Gauss-Seidel relaxation needs few sweeps (CollisionSettings::maxSweepsGaussSeidel),
    // a Jacobi one many more. Asked after each listContacts (the CUDA backend falls back to Jacobi for
    // a listing it cannot colour).
    virtual bool relaxesGaussSeidel() const { return false; }
    // What the last relaxation leaves the next step's (ContactCarryOver): checkpoints carry it so that a
    // restarted run stays bit-identical, and World edits carry it over to the particles' new slots.
    // Empty from a backend that does not warm-start or before anything rested. Setting the state
    // forgets it (indices may mean other particles). Restoring drops records that cannot be used
    // (isUsableWarmStart) and all the colours where they are no colouring of the records (another
    // count, a colour out of range, two contacts of a particle sharing one): the next listing colours
    // afresh.
    virtual ContactCarryOver contactWarmStart() const { return {}; }
    virtual void restoreContactWarmStart(const ContactCarryOver& /*carried*/) {}
    // The step about to run, counted from the simulation's start (Simulation::step; a restart goes on
    // from its checkpoint's): a schedule that repeats every few steps keys on it, so that a restarted
    // run repeats it.
    virtual void beginStep(int64_t /*step*/) {}
    // Lists every particle's contacts (pairs and walls within the contact margin) from the current
    // positions and keeps those positions; returns the number of listed contacts (0: nothing to do).
    // `resting`: which touching contacts are stopped too (relaxParticle).
    virtual int64_t listContacts(const RestingContact<double>& resting) = 0;
    // The deepest overlap of the last listing's contacts, as a fraction of the contact distance
    // (ContactResidual::overlap), or -1 where the backend does not measure it: then the first sweep's
    // overlap stands for it (collision_rounds.cpp: a deep one lists again). A Jacobi sweep measures it
    // on the listed positions; the CPU's bottom-up Gauss-Seidel sweep on positions its earlier updates
    // moved, so a column's lifts add up along it, and that larger measure is what the CPU's relisting
    // was tuned on (measured at the listing instead, the 400-ball pile of
    // DenseContact.ASettledPileHoldsEveryLayer fell at 0.0112 per ball, above the test's 0.0102). The
    // GPU's coloured sweeps measure it at the listing (contact_gauss_seidel.cu).
    virtual double listedOverlap() const { return -1; }
    // Runs `sweeps` sweeps over the listed contacts (Gauss-Seidel or Jacobi, contact_relaxation.h);
    // returns the residual of the last one.
    virtual ContactResidual<double> relaxContacts(int sweeps) = 0;
    // A listing's whole relaxation on the plan's schedule (RelaxationPlan): the first sweep alone, then
    // batches until the residual is within tolerance at the end of a batch or the cap is reached. The
    // default runs it from here, a read-back per batch; a backend may run the same schedule where its
    // sweeps run (the CUDA backend: one kernel, no host round trip), with the same result.
    virtual RelaxationOutcome relaxListing(const RelaxationPlan& plan) {
        RelaxationOutcome outcome;
        outcome.first = outcome.last = relaxContacts(1);
        outcome.sweeps = 1;
        while (plan.continuesAfter(outcome.sweeps, outcome.last, outcome.first.overlap)) {
            const int batch = std::min(plan.batch, plan.sweepCap(outcome.first.overlap) - outcome.sweeps);
            outcome.last = relaxContacts(batch);
            outcome.sweeps += batch;
        }
        return outcome;
    }
    // The relaxation of this listing is over: a backend whose sweeps carry momentum (the accelerated
    // Jacobi sweeps) leaves its velocities with the projected impulses (settleRow). Called before
    // contactLiftWork and contactImpulses.
    virtual void endRelaxation() {}
    // Work done against gravity by the position moves since listContacts: sum of -m g . dx [eps].
    virtual double contactLiftWork() = 0;
    // Impulses of the velocity level since listContacts (impulse_sums.h): what the walls received and
    // r_ij . J_ij of the pair contacts, summed in a fixed order.
    virtual ImpulseSums contactImpulses() = 0;

    // ---- reductions ----
    virtual double kineticEnergy() = 0;  // O(N)
    virtual void scaleVelocities(double alpha) = 0;
    virtual EnergySums energies() = 0;  // includes the pair potential (a force pass)
    // sum over pairs i < j of r_ij . F_ij at the current positions (the pair-force virial of the
    // pressure, pressure.h) [eps]; 0 without pair forces. An O(N^2) pass like energies().
    virtual double pairVirial() = 0;
    virtual HealthReport health() = 0;  // non-finite values, particles outside the box
    virtual StepCheck checkStep() { return StepCheck{kineticEnergy(), health()}; }

    // ---- timing and output ----
    virtual void markPhase(StepPhase phase) = 0;
    // The phases of the step between the last Integrate and Done marks; a backend that reads them
    // without a wait (CUDA) may report a step whose marks are not done yet with the next one instead.
    virtual PhaseSeconds phaseSeconds() = 0;
    virtual void writeInstances(const InstanceTarget& target) = 0;
    virtual void finish() = 0;  // returns when all queued work is done (benchmarks, interop)
};

}  // namespace corebox
