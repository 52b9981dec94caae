// corebox as a library: a World of hard-core balls in a rigid box, stepped by your program.
//
// Design note.
// - One object, World, made from a plain definition (WorldDef, in the style of Box2D's b2WorldDef:
//   every field has a default and a unit) or from a scene file. It owns one simulation on the CPU
//   (every core) or on CUDA GPUs, in fp32 or fp64. The header carries no GL, CUDA, ImGui or CLI11:
//   the implementation sits behind a pointer (pimpl), so the library can change without breaking you.
// - Particles have stable ids (ParticleId): an id is never reused in a world, and survives the
//   removal of others. Ids count up from 0 in the order particles are added (the initial ones first),
//   so a table indexed by id is a map from ids. Internally particles live in slots that removal
//   compacts; the id <-> slot maps are the World's business.
// - Edits between steps (add, remove, impulses, teleports, velocities, fields) are collected on a host
//   copy of the state and reach the simulation, in one upload, at the next step. The energy they bring
//   in is counted as external work, so the energy balance (energy()) still closes.
// - step(dt) takes one step; advance(frameTime) is the game loop: an accumulator of frame time spent
//   in fixed substeps of WorldDef::substep, at most maxSubsteps per call (what is left over beyond that
//   is dropped and reported, so a slow frame cannot snowball). Same calls, same results, bit for bit,
//   on the same backend and thread count (stateHash() compares).
// - Reading state: positions(), velocities(), ids() and speciesOf() are spans into a host mirror of
//   the state, refreshed on request (the first read after a step downloads once; later reads are
//   free; a read of positions() alone downloads only the positions: half the bytes, what drawing needs).
//   CUDA users can instead read the GPU arrays in place (deviceState()) and order their kernels
//   after the world's stream.
// - contacts(): the impacts of the last step() or advance(), each a particle pair or a wall hit with
//   its normal, impulse and time, as games need for sounds and effects. Resting contacts held by the
//   contact solver (a pile pressing on the floor) are not impacts and are not listed.
// - Threads: a World is not synchronised. Call it from one thread at a time, but from any thread: each
//   call that reaches a GPU first makes the world's device current on the calling thread, and leaves it
//   current there. The sandbox example steps its world on a worker thread while its main thread draws
//   the frame before.
// - Errors are exceptions (errors.h: InputError for bad input or unknown ids, InstabilityError for a
//   blow-up, DeviceError for GPUs), because each carries a message a user can act on and C++ callers
//   should not have to check every call. corebox_c.h maps them to error codes plus a message for
//   other languages' foreign-function interfaces, where exceptions cannot cross. An InputError changes
//   nothing; after an InstabilityError or a DeviceError from a step the world holds the failed step's
//   state and should be made again.
//
// Units are the model's reduced units (DESIGN.md sec. 2): lengths in sigma, masses in m, time in tau,
// energies in m sigma^2 / tau^2. A game can read them as metres, kilograms and seconds: gravity
// {0, -9.81, 0} is Earth's, and a ball of radius 0.5 is a metre across.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "corebox/device_state.h"
#include "corebox/errors.h"
#include "corebox/export.h"
#include "corebox/types.h"

namespace corebox {

// A point or vector in the box [sigma], [sigma / tau], [sigma / tau^2] or [m sigma / tau].
struct Vec3d {
    double x = 0, y = 0, z = 0;
};

// A particle's id: stable for its life, never reused in a world.
using ParticleId = uint64_t;
constexpr ParticleId kNoParticle = ~ParticleId(0);

// A contiguous read-only view (C++17 has no std::span). Valid until the next call that edits or steps
// the world.
template <class T>
struct Span {
    const T* data = nullptr;
    size_t size = 0;
    const T* begin() const { return data; }
    const T* end() const { return data + size; }
    const T& operator[](size_t i) const { return data[i]; }
    bool empty() const { return size == 0; }
};

// A kind of particle.
struct ParticleSpecies {
    std::string name = "ball";     // unique within the world
    double mass = 1.0;             // [m], > 0
    double radius = 0.5;           // hard-core radius [sigma], > 0: two balls collide at R < a_i + a_j
    // Lennard-Jones pair force (DESIGN.md sec. 2), off by default: game balls are pure hard spheres.
    double epsilon = 0.0;          // well depth [m sigma^2 / tau^2]; 0: no pair force
    double sigma = 1.0;            // LJ length [sigma]
    Vec3d acceleration{0, 0, 0};   // this species' own uniform acceleration, added to gravity [sigma / tau^2]
    std::array<float, 3> color{0.8f, 0.3f, 0.2f};  // linear RGB in [0, 1], for your renderer
};

// Everything a world is made from. Creation-time: box, species, backend, precision, threads.
// Live (setters on World): gravity, species accelerations, restitution.
struct WorldDef {
    Vec3d boxSize{30, 60, 30};        // edge lengths [sigma]; walls at 0 and L on each axis
    double wallRestitution = 0.5;     // e_w in [0, 1]: v_n' = -e_w v_n at a wall
    double restitution = 0.5;         // ball-ball e in [0, 1] (Newton's law along the line of centres)
    Vec3d gravity{0, -9.81, 0};       // uniform acceleration of every species [sigma / tau^2]
    std::vector<ParticleSpecies> species{ParticleSpecies{}};  // at least one
    double cutoff = 0.0;              // LJ cutoff r_c [sigma] (neighbour lists); 0: all pairs
    // Integrator: "verlet" (default: symplectic, one force pass a step), or any of `corebox --help`'s
    // methods ("rk4", "pefrl", ...).
    std::string method = "verlet";
    double substep = 1.0 / 240.0;     // the fixed step of advance() [tau]; also step()'s default
    int maxSubsteps = 8;              // advance() takes at most this many substeps per call
    BackendKind backend = BackendKind::Cpu;
    Precision precision = Precision::Fp64;
    int threads = 0;                  // CPU threads; 0: every hardware thread
    int gpus = 1;                     // CUDA devices, from `device` on; 0: the measured best for the count
    int device = 0;                   // first CUDA device ordinal
    Exchange exchange = Exchange::Auto;  // how several GPUs share positions
    bool recordContacts = true;       // contacts() lists the impacts; false saves a record per impact
    // contacts() lists only impacts whose impulse magnitude is at least this [m sigma / tau]; 0: every
    // impact. The others cost no record: a game that flashes or plays sounds only above a threshold
    // sets it. A landing pile resolves millions of soft impacts a second, and recording, copying and
    // ordering them all is work the simulation never needed. The sandbox at 10^5 balls on one H200 (420
    // scripted frames, fp32, pipelined): 42.2 and 40.7 ms a frame on average with every impact recorded,
    // 22.2 and 23.4 with none (docs/results/sandbox_impact_records/, one call), 24.3 with those of
    // impulse >= 5, the ones that flash, 2% of them (docs/results/sandbox_h200_fp32_100000.json, a later
    // call); the same state in all. The threshold is compared in double; backends agree on impulses to
    // rounding, so an impact within rounding of it may be listed by one backend and not another.
    double contactMinImpulse = 0.0;
    // Cap on the contact solver's sweeps per listing, a game engine's solver iterations (resting contacts
    // are relaxed by sweeps after the impacts: kernels/contact_relaxation.h); 0: corebox's own, 16
    // Gauss-Seidel sweeps (128 where the GPU falls back to Jacobi sweeps for a listing). A shallow
    // pile rests as well with fewer: 2,000 balls two to three layers deep (CPU, fp64, 8 s, `corebox bench
    // pile --contact-sweeps 4|8|16`) came to rest at the same time, overlaps within 5e-5 of a diameter and
    // the energy balance exact, at 8.0 / 10.3 / 14.9 ms a frame once settled. A pile 40 layers deep needs
    // the 16 (fewer: it rattles, lists its contacts again and takes more impact rounds).
    int contactSweeps = 0;
    // Cap on the impact rounds per step, a game engine's collision iterations
    // (kernels/collision_resolution.h: a round resolves every particle's earliest impact where it is
    // also its partner's; a chain of impacts through a stack takes a round a ball); 0: corebox's own,
    // 64; at most 4096. What a capped step leaves goes to the contact solver, which stops those
    // contacts (restitution 0; a contact alone at both its balls still bounces) instead of bouncing
    // them: energy is never gained, a dense landing bounces less. Where it pays: a landing of many
    // balls at once, whose impact chains hit any cap. The sandbox example at 10^5 balls (one H200,
    // fp32, scripted, one call) with caps 64 / 32 / 16 / 8: 15.1 / 14.1 / 13.7 / 13.7 ms a frame, the
    // slowest 68 / 54 / 49 / 47 (the landing's contact phase stays), the cap hit in 87 / 117 / 150 /
    // 211 of 1680 steps, 21 / 19 / 14 / 9 million pair impacts; the same rest and overlaps.
    int impactRounds = 0;
    // Cap on the contact solver's listings per step: a listing whose overlaps were deeper than 2% of a
    // diameter when it was made is listed again after its sweeps (their moves bring neighbours into
    // contact); 0: corebox's own, kMaxContactListings. What the last listing leaves, the next step's
    // contact solver takes on, as a game engine's fixed iteration budget does
    // (StepInfo::overlapLeft says how deep). Where it pays: a landing of many balls at once; the
    // sandbox example sets 2 (docs/library.md: its landing at 10^5 balls on an H200 a sixth faster,
    // the deepest overlap a step left 0.8% of a diameter against 0.6%; with one listing 6.5%).
    int contactListings = 0;
    static constexpr int kMaxContactListings = 32;
};

// One particle to add.
struct ParticleDef {
    int species = 0;              // index into WorldDef::species
    Vec3d position{0, 0, 0};      // centre [sigma]; must leave the hard core inside the box
    Vec3d velocity{0, 0, 0};      // [sigma / tau]
};

// The outcome of adding or moving a particle. A request whose hard core would overlap another
// particle or a wall is rejected, never silently shifted: `placed` is false and `reason` says why.
struct PlacementResult {
    bool placed = false;
    ParticleId id = kNoParticle;         // the particle added or moved (kNoParticle when an add failed)
    ParticleId blockedBy = kNoParticle;  // the particle it would overlap, if that was the reason
    std::string reason;                  // empty when placed
    explicit operator bool() const { return placed; }
};

enum class ContactKind { Pair, Wall };

// One impact of the last step() or advance().
struct Contact {
    ContactKind kind = ContactKind::Pair;
    ParticleId a = kNoParticle;   // the particle
    ParticleId b = kNoParticle;   // the other particle (kind Pair); kNoParticle for a wall
    int wallAxis = -1;            // kind Wall: 0 x, 1 y, 2 z
    int wallSide = -1;            // kind Wall: 0 the wall at 0, 1 the wall at L
    double time = 0;              // since the start of the step() or advance() call [tau]
    Vec3d normal{0, 0, 0};        // unit, from b to a (a wall: into the box)
    double impulse = 0;           // normal impulse on a; b receives its opposite [m sigma / tau]
    double speed = 0;             // normal approach speed at contact [sigma / tau]
};

// What one step() or advance() did.
struct StepInfo {
    int substeps = 0;                 // steps taken
    double simulatedTime = 0;         // [tau]
    double droppedTime = 0;           // advance(): frame time beyond maxSubsteps, discarded [tau]
    double alpha = 0;                 // advance(): accumulator / substep in [0, 1), to interpolate drawing
    int64_t pairCollisions = 0;
    int64_t wallCollisions = 0;
    double dissipated = 0;            // kinetic energy lost in inelastic impacts and contacts [m sigma^2 / tau^2]
    int roundCapHits = 0;             // steps whose impact rounds hit their cap (dense piles)
    double seconds = 0;               // wall time of the call [s]
    // Of `seconds`, what the collision stage took [s]: the impact rounds, and the contact phase
    // (resting contacts and piles), of which building its contact lists. Host clock: on a GPU a part
    // also holds the device work queued before it that its first wait waits for (the integration's
    // kernels end inside the impact rounds' time). The rest is the integration as the host saw it,
    // edits flushed to the backend and the contact records.
    double secondsImpacts = 0, secondsContacts = 0, secondsListings = 0;
    // The contact phase: the contact lists it made (a landing lists again where overlaps are deep;
    // WorldDef::contactListings caps them a step), and the deepest overlap it left at the end of a step,
    // as its last sweep measured it [fraction of a contact distance]. What one step leaves, the next
    // step's contact phase takes on.
    int contactListings = 0;
    double overlapLeft = 0;
};

// The energy balance [m sigma^2 / tau^2]: kinetic + potential + dissipated - external stays constant
// up to integration error (and rounding) whatever the world went through.
struct EnergyBalance {
    double kinetic = 0;
    double potential = 0;     // pair potential plus -m g.x of every particle
    double dissipated = 0;    // lost in inelastic impacts and contacts since the world was made
    double external = 0;      // brought in by edits: particles added and removed, impulses, teleports,
                              // velocities set, field changes
    Vec3d momentum{0, 0, 0};  // total [m sigma / tau]
    double conserved() const { return kinetic + potential + dissipated - external; }
};

class COREBOX_API World {
public:
    // Throws InputError naming the field when the definition breaks a rule (a mass <= 0, a restitution
    // outside [0, 1], an unknown method), DeviceError when the backend cannot be had.
    explicit World(const WorldDef& def);
    // A world from a scene file (DESIGN.md sec. 3: box, species, interaction, integrator, the initial
    // particles with ids 0 .. N-1, its thermostat if it has one), on `def`'s backend, threads, device,
    // recordContacts and contactMinImpulse; the scene's precision, [devices], dt (as substep) and
    // [interaction] (its contact_sweeps, contact_listings and max_collision_rounds too) apply.
    static World fromSceneFile(const std::string& path, const WorldDef& def = WorldDef{});
    ~World();
    World(World&&) noexcept;
    World& operator=(World&&) noexcept;
    World(const World&) = delete;
    World& operator=(const World&) = delete;

    // ---- species ----
    int speciesCount() const;
    const ParticleSpecies& species(int index) const;
    int speciesIndex(const std::string& name) const;  // -1 when there is none
    // Adds a species; returns its index. Applies from the next step.
    int addSpecies(const ParticleSpecies& species);

    // ---- particles (between steps) ----
    PlacementResult addParticle(const ParticleDef& particle);
    // Each checked against the world and the ones before it; the results in the same order.
    std::vector<PlacementResult> addParticles(const std::vector<ParticleDef>& particles);
    // Throws InputError for an id not in the world.
    void removeParticle(ParticleId id);
    bool contains(ParticleId id) const;
    size_t particleCount() const;

    // v += J / m at the start of the next step (exactly: momentum changes by J).
    void applyImpulse(ParticleId id, Vec3d impulse);
    void setVelocity(ParticleId id, Vec3d velocity);
    // Teleports a particle; rejected (and reported) when its hard core would overlap another or a wall.
    PlacementResult setPosition(ParticleId id, Vec3d position);
    Vec3d position(ParticleId id);
    Vec3d velocity(ParticleId id);
    int speciesOf(ParticleId id) const;

    Vec3d boxSize() const;  // edge lengths [sigma]; walls at 0 and L on each axis

    // ---- fields and materials (live) ----
    void setGravity(Vec3d gravity);
    Vec3d gravity() const;
    void setSpeciesAcceleration(int species, Vec3d acceleration);
    void setRestitution(double ballBall, double wall);

    // ---- stepping ----
    StepInfo step();          // one step of WorldDef::substep
    // One step of dt [tau] > 0. A dt other than the last step's re-configures the integrator (with LJ
    // forces a force pass): games should keep a fixed step (advance()).
    StepInfo step(double dt);
    StepInfo advance(double frameTime);  // the game loop (see the design note)
    double time() const;        // simulated [tau]
    int64_t stepCount() const;

    // ---- reading state (spans into the host mirror; see the design note) ----
    Span<ParticleId> ids();          // the id of each slot
    Span<Vec3d> positions();         // by slot [sigma]
    Span<Vec3d> velocities();        // by slot [sigma / tau]
    Span<int32_t> speciesIndices();  // by slot
    DeviceState deviceState();       // backend Cuda: the arrays on the GPU; device -1 otherwise

    // ---- contacts and queries ----
    const std::vector<Contact>& contacts() const;  // impacts of the last step() or advance()
    // Every particle whose centre lies within `radius` [sigma] of `centre`, by ascending id.
    std::vector<ParticleId> queryRadius(Vec3d centre, double radius);

    // ---- bookkeeping ----
    EnergyBalance energy();  // a reduction over the particles (with LJ forces: a force pass)
    uint64_t stateHash();    // FNV-1a over the exact bits of ids, positions, velocities and species
    std::string backendName() const;  // "cpu (CPU model)" or "cuda (GPU model ...)", for logs

private:
    struct Impl;
    std::unique_ptr<Impl> m_impl;
    explicit World(std::unique_ptr<Impl> impl);
};

}  // namespace corebox
