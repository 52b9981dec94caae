// Host memory a run of a scene needs, estimated before anything is allocated, so that a scene too
// large for this machine is refused with the sizes named (an input error, exit code 2) instead of
// ending in std::bad_alloc halfway through setup, or in the kernel's out-of-memory killer.
//
// Design note. The estimate is deliberately coarse: bytes per particle for the state, its copies
// (initial state, last good state) and the CPU backend's arrays (positions, velocities,
// accelerations, the integrator's stages, collision bookkeeping, the cell list), plus the lattice
// placement's shuffled site list, which grows with the box rather than with N (a very long box).
// It is compared with the machine's physical memory, not with what is free at this instant: the
// point is to refuse what can never fit, not to second-guess the allocator.
#pragma once

#include <cstdint>
#include <string>

#include "scene.h"

namespace corebox {

// Sites of the lattice placement (packing.cpp's latticeSites) in double, 0 for other placements:
// the count it will allocate, computed without its int64 arithmetic, which a very long box overflows.
double latticeSiteCount(const Scene& scene);
// Bytes the host needs to set up and run `scene` on the CPU backend.
double estimatedHostBytes(const Scene& scene);
// Physical memory of this machine in bytes (0 when unknown).
double physicalMemoryBytes();
// "1.5 GiB", "3.2 TiB", ...
std::string formatBytes(double bytes);
// Throws InputError naming the particle count, the estimate and the memory of the machine when the
// estimate exceeds it.
void checkHostMemory(const Scene& scene);

}  // namespace corebox
