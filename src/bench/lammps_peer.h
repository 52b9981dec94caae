// LAMMPS as the peer of `corebox bench md`: the same starting state (positions and velocities of the
// corebox run) written as a LAMMPS data file, the same model (lj/cut 2.5 with no shift, fix nve,
// fix wall/reflect where corebox's walls stop a centre: a and L - a), run with MPI ranks, timed by
// LAMMPS' own "Loop time" line (setup excluded).
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "particle_state.h"
#include "scene.h"

namespace corebox {

struct LammpsTiming {
    double secondsPerStep = 0;
    int64_t steps = 0;
    std::string version;  // LAMMPS' banner line
};

// The lmp binary to use for `request` ("auto": lmp on PATH, "off": none, else a path), or "".
std::string findLammps(const std::string& request);

// Runs `steps` steps of `scene` from `initial` in a scratch directory; nullopt (and a message on
// stderr) when LAMMPS fails.
std::optional<LammpsTiming> runLammps(const std::string& lmp, int ranks, const Scene& scene, const ParticleState& initial, int64_t steps);

}  // namespace corebox
