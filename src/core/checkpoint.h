// Checkpoints: everything a run needs to go on exactly where it stopped, so that a run restarted from
// a checkpoint is bit-identical to one that never stopped (same backend and precision).
//
// Design note. What outlives a step is small and lives in the core, not in the backends: the state
// (positions, velocities, species), the running scene with its live edits, the step and time, the
// energy bookkeeping (dissipated, thermostat, parameter work, the conserved sum's base and scale),
// the counters and pressure window since the last observables row, and the adaptive controller's next
// dt. The backends hold nothing else that a step reads but Verlet's cached accelerations and the
// contact relaxation's impulses that warm-start the next step (carried when the backend keeps them:
// Backend::contactWarmStart) with the colours the CUDA backend's next listing may keep. The accelerations are
// carried when they are not what a force pass at X gives bit for bit (the all-pairs update after
// collisions, CPU and one GPU, exchanges the old pair forces of the moved particles for new ones:
// Backend::cachedAccelerations); otherwise they are recomputed from the restored X bit for bit (the force pass has a
// fixed summation order, and neighbour lists, rebuilt at restore, sum each particle's partners by ascending index), the
// thermostat's and placement's random numbers are counter-based on (seed, step, particle), and an
// fp32 backend's state survives the round trip through double exactly.
//
// File format (binary, little-endian, doubles as IEEE 754 bits): the magic "corebox checkpoint\n",
// a format version, a byte-order and size probe, the payload (length-prefixed scene TOML, scalars,
// then N and the arrays, then the count of cached accelerations, 0 or N, and those, then the count of
// warm-start impulses and those as (i, partner, lambda), then the count of their colours, 0 or one an
// impulse, and those as bytes; files of versions 1 to 3, without the last parts, are read too), and an
// FNV-1a 64 hash of everything before it. A file that is truncated,
// foreign, from another version or damaged is refused with a message naming the file.
#pragma once

#include <cstdint>
#include <string>

#include "contact_relaxation.h"  // ContactWarmStart
#include "impulse_sums.h"
#include "particle_state.h"

namespace corebox {

struct SimulationCheckpoint {
    std::string sceneToml;  // the running scene (sceneToToml), live edits included
    ParticleState state;
    int64_t step = 0;
    double time = 0;
    double dissipated = 0;
    double thermostatEnergy = 0;
    double parameterWork = 0;
    double conserved0 = 0;  // the conserved sum's base (re-based by live edits of the potential)
    double energyScale = 1;
    double lastKinetic = 0;
    int64_t pairCollisions = 0;  // since the last observables row
    int64_t wallCollisions = 0;
    int64_t roundCapHits = 0;
    double dtNext = 0;  // the adaptive controller's next step (0: not adaptive yet)
    double pressureTime = 0, pressureKineticTime = 0;  // the pressure window since the last row
    ImpulseSums pressureImpulses;
    // Verlet's cached accelerations when a force pass would not reproduce them bit for bit; empty:
    // recomputed at restore.
    std::vector<Vec3<double>> accelerations;
    // The contact relaxation's warm-start impulses (Backend::contactWarmStart); empty: a cold start.
    std::vector<ContactWarmStart> contactImpulses;
    // Their Gauss-Seidel colours, one a record (ContactCarryOver::colours); empty: the backend keeps
    // none, or a checkpoint older than version 4.
    std::vector<uint8_t> contactColours;
};

// The FNV-1a 64 hash a checkpoint file ends with, of every byte before it.
uint64_t checkpointChecksum(const std::string& bytes);

// Writes atomically (temp file and rename); an existing checkpoint at `path` is kept as path.prev
// first, so a crash while writing never leaves the run without one. Throws InputError.
void writeCheckpoint(const std::string& path, const SimulationCheckpoint& checkpoint);

// Throws InputError naming the file when it cannot be read or is not a whole checkpoint of this
// format (truncated, foreign, another version, damaged).
SimulationCheckpoint readCheckpoint(const std::string& path);

}  // namespace corebox
