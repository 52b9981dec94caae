// The end-of-step check of one particle, shared by launchHealth (reduce_kernels.cu) and the kernels that
// fold it into another pass (step_kernels.cu, collision_kernels.cu).
#pragma once

#include "energy_terms.h"
#include "gpu_launch.h"
#include "rk_stage.h"

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

// ListForecastArgs for particle i at (x, v) with acceleration a.
template <class Real>
__device__ inline void forecastParticle(const ListForecastArgs<Real>& f, int64_t i, Vec3<Real> x, Vec3<Real> v, const Vec3<Real>& a) {
    verletKick(v, a, f.h);
    verletDrift(x, v, f.dt);
    const Vec3<Real> built = f.xBuilt[i];
    if (!(norm2(x - built) <= f.limit2)) *f.moves = 1u;  // NaN included
    if (!f.hint) return;
    verletKick(v, a, Real(2) * f.h);  // the next step's two half kicks, with this acceleration
    verletDrift(x, v, f.dt);
    if (!(norm2(x - built) <= f.limit2)) *f.hint = 1u;
}

}  // namespace corebox::gpu
