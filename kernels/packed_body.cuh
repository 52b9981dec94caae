// A particle's position or velocity as a PackedBody (gpu_launch.h) and back (vec3Of, packed): the
// contact phase's copy of the state, which a thread reads and writes whole in one vector access. The
// kernels that walk contacts read each neighbour's position and velocity at a random place: as three
// scalars each, every one its own 32-byte sector; packed, one sector each (contact_gauss_seidel.cu has
// the evidence).
#pragma once

#include "gpu_launch.h"
#include "vec3.h"

namespace corebox::gpu {

template <class Real>
__device__ inline Vec3<Real> vec3Of(const PackedBody<Real>& b) {
    return Vec3<Real>{b.x, b.y, b.z};
}

template <class Real>
__device__ inline PackedBody<Real> packed(const Vec3<Real>& r, Real w) {
    return PackedBody<Real>{r.x, r.y, r.z, w};
}

}  // namespace corebox::gpu
