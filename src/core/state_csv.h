// Particle state files: CSV with the header `id,species,x,y,z,vx,vy,vz` (DESIGN.md sec. 3). Written
// with 17 significant digits so a double state survives a round trip bit for bit.
#pragma once

#include <istream>
#include <string>

#include "particle_state.h"

namespace corebox {

// Throws InputError naming the file and line for a missing file, a wrong header, a malformed or
// non-finite number, a negative species, or ids that are not exactly 0..N-1 (any order).
ParticleState readStateCsv(const std::string& path);
// The same from a stream; `sourceName` names it in the messages.
ParticleState parseStateCsv(std::istream& in, const std::string& sourceName);

// Atomic: the file appears complete or not at all.
void writeStateCsv(const std::string& path, const ParticleState& state);

}  // namespace corebox
