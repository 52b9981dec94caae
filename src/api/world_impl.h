// The state behind corebox::World (world.h): the scene it runs, the simulation, and the host mirror
// that edits and reads go through.
//
// Design note.
// - The mirror (slot order: ids, positions, velocities, species) is the one copy a user edits. It is
//   downloaded from the backend at the first read or edit after a step (`positionsFresh`,
//   `velocitiesFresh`: reading positions alone downloads only them, half the bytes; the sandbox at 10^5
//   balls on an H200 spent 2.2 ms a frame downloading and converting both), and uploaded
//   in one piece at the next step when it was edited (`edited`): any number of edits between two steps
//   costs one upload. Slots are compacted by swap-remove, so slot order depends only on the calls made
//   (determinism) and ids map to slots through a hash map.
// - The Simulation exists only while there are particles: the CUDA backend has no use for an empty
//   state. It is made at the first step with particles and dropped when the last one is removed; the
//   energy bookkeeping of dropped simulations carries over (`m_pastDissipated`, `m_pastExternal`).
// - External work is the sum of what edits brought in: the first state's E_kin + E_pot, each
//   replacement's difference (Simulation::replaceParticles), live edits of fields (parameterWork) and
//   what a thermostat of a scene file gave. conserved() = K + U + D - external then stays at 0 up to
//   integration error.
// - Edits keep a resting pile's contact impulses. Uploading a state makes a backend forget the last
//   step's impulses (its indices may mean other particles), which warm-start the next step's contact
//   phase; a pile that lost them starts its relaxation from nothing and sinks into itself for a step
//   or more. `simIndex` remembers which index each slot had in the simulation, so flushEdits carries
//   the impulses of the contacts whose particles are still there over to their new slots. New and
//   teleported particles carry none.
// - The overlap checks of adds and teleports and the radius query use a grid over the mirror
//   (slot_grid.h), rebuilt lazily after steps, removals and adds that outgrew it.
#pragma once

#include <memory>
#include <unordered_map>
#include <vector>

#include "backend_factory.h"
#include "corebox/world.h"
#include "scene.h"
#include "simulation.h"
#include "slot_grid.h"

namespace corebox {

struct World::Impl {
    Impl(const WorldDef& def, Scene scene);

    // ---- mirror ----
    // Makes the calling thread ready for the backend (its GPU current on CUDA): a World may be driven
    // from one thread and then another (the sandbox steps on a worker), so every path that reaches
    // the backend starts here.
    void bindThread();
    void ensureMirror();     // download the state when a step made the mirror stale
    void ensurePositions();  // the positions alone (reads that draw or query need no velocities)
    void ensureGrid();       // the overlap grid over the current mirror
    uint32_t slotOf(ParticleId id) const;  // throws InputError for an unknown id
    // Why a core of species `species` centred at x does not fit: a wall or the particle it overlaps
    // (skipping slot `self`); an empty reason when it fits.
    PlacementResult checkPlacement(int species, const Vec3d& x, uint32_t self) const;
    void appendSlot(ParticleId id, const ParticleDef& p);
    void removeSlot(uint32_t slot);

    // ---- simulation ----
    void flushEdits();  // uploads the edited mirror (and species) to the simulation
    void markSimulationInSync();  // slot k is the simulation's particle k
    // The simulation's contact impulses and their colours (indices of its state, `simCount` particles) for
    // the slots about to replace that state: contacts whose particles were both kept, at their slots. A
    // renumbering keeps the colours a colouring (no two contacts of a particle shared one before).
    ContactCarryOver carriedImpulses(const ContactCarryOver& contacts, int64_t simCount) const;
    void dropSimulation();
    // Applies the live parameters of m_scene (fields, restitution, dt) to the running simulation.
    void applyLiveParameters();
    StepInfo stepOnce(double dt, double timeOffset, StepInfo info);
    double externalWork() const;
    double dissipated() const;

    WorldDef def;        // the definition (backend, precision, threads, substep, maxSubsteps)
    Scene scene;         // species, box, interaction and integrator as the world runs them
    std::vector<ParticleSpecies> species;  // the public view of scene.species
    BackendChoice choice;
    std::unique_ptr<Backend> idleBackend;  // made up front (device errors at construction), used by the first simulation
    std::unique_ptr<Simulation> sim;

    std::vector<ParticleId> ids;
    std::vector<Vec3d> positions, velocities;
    std::vector<int32_t> speciesIndex;
    // The state read back (ensureMirror) and the state handed to the simulation (flushEdits), kept for its
    // memory and converted on the World's threads: an edit at 10^5 balls on an H200's host spent 2.4 to
    // 2.7 ms building a fresh one on one thread (page faults) and 2.3 to 2.6 reading the mirror back (host
    // timestamps, the sandbox example). With this and CudaDevice's kept, parallel conversions the
    // sandbox's edit frames took 4.4 to 7.5 ms of simulation against 7.1 to 9.6 (fp32, one call).
    ParticleState stateBuffer;
    std::vector<ContactRecord> logBuffer;  // a step's contact log, kept for its memory
    std::vector<int64_t> simIndex;  // per slot: its index in the simulation's state; -1: added or teleported since
    std::unordered_map<ParticleId, uint32_t> slots;
    ParticleId nextId = 0;
    bool positionsFresh = true, velocitiesFresh = true;  // the mirror's arrays as the simulation has them
    bool edited = false;
    SlotGrid grid;
    bool gridFresh = false;
    double maxRadius = 0;

    std::vector<Contact> contacts;
    double time = 0;
    int64_t steps = 0;
    double accumulator = 0;
    double pastDissipated = 0;  // from simulations dropped when the world emptied
    double pastExternal = 0;
    double simulationBase = 0;  // E_kin + E_pot of the current simulation's first state
};

}  // namespace corebox
