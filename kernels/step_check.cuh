// The end-of-step check of one particle, shared by launchHealth (reduce_kernels.cu) and the kernels that
// fold it into another pass (step_kernels.cu, collision_kernels.cu).
#pragma once

#include "energy_terms.h"
#include "gpu_launch.h"

namespace corebox::gpu {

// Counts particle i into the health words when it is not finite or outside the box (its index among
// the first five examples).
template <class Real>
__device__ inline void countIfUnhealthy(const HealthArgs<Real>& h, int64_t i) {
    const Vec3<Real> x = h.p.x[i], v = h.p.v[i];
    bool finite = true, inside = true;
    for (int k = 0; k < 3; ++k) {
        finite = finite && isfinite(double(x[k])) && isfinite(double(v[k]));
        inside = inside && x[k] >= Real(0) && x[k] <= h.box[k];
    }
    if (finite && inside) return;
    atomicAdd(&h.counts[finite ? 1 : 0], 1ull);
    const unsigned long long slot = atomicAdd(&h.counts[2], 1ull);
    if (slot < 5) h.examples[slot] = i;
}

// The health count above, and particle i's kinetic energy into kineticRow[i].
template <class Real>
__device__ inline void checkParticle(const HealthArgs<Real>& h, const SpeciesTable<Real>& table, int64_t i, double* kineticRow) {
    kineticRow[i] = kineticEnergyOf(double(table.mass[h.p.species[i]]), vec3Cast<double>(h.p.v[i]));
    countIfUnhealthy(h, i);
}

}  // namespace corebox::gpu
