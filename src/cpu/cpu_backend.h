// CPU reference backend: the oracle every GPU path is compared with. Clarity first, every core
// used (OpenMP over particles), and deterministic whatever the thread count: each particle's sums
// run over partners in index order, and every reduction over particles is made in fixed-size
// chunks added in chunk order.
//
// Forces follow the model's choice (force_model.h). All pairs: each pair evaluated from both sides,
// the same arithmetic as the GPU tiles, so CPU and GPU differ only by rounding order, never by
// formula. Neighbour lists (verlet_list.h, list_forces.h): half lists, each pair evaluated once
// (Newton's third law) and added to both particles, every particle's sum by ascending partner index.
// The end-of-step list pass also screens the collision stage (screenStage): steps with nothing near
// contact skip it, steps with wall hits alone resolve them at once. After a collision stage the
// cached accelerations are updated for the moved particles' pairs only (refreshAccelerations).
#pragma once

#include <memory>

#include "backend.h"

namespace corebox {

struct CpuBackendOptions {
    Precision precision = Precision::Fp64;
    int threads = 0;  // 0: all hardware threads (or OMP_NUM_THREADS)
    // A stage's first impact round searches from the particles fast enough for an impact
    // (collision_resolution.h: startsActive); false: from every particle (the same bits, for tests).
    bool moversFirst = true;
};

std::unique_ptr<Backend> makeCpuBackend(const CpuBackendOptions& options);

}  // namespace corebox
