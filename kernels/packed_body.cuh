// A particle's position or velocity as a PackedBody (gpu_launch.h) and back (vec3Of, packed): the
// contact phase's copy of the state, which a thread reads and writes whole in one vector access. The
// kernels that walk contacts read each neighbour's position and velocity at a random place: as three
// scalars each, every one its own 32-byte sector; packed, one sector each (contact_gauss_seidel.cu has
// the evidence). A particle's two bodies sit side by side (xBody, vBody: ContactArgs::body[2i], [2i + 1]):
// in fp32 one 32-byte sector holds both, so the second read of a particle hits the line the first
// brought into L1 instead of going to L2 again.
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

template <class Real>
__device__ inline PackedBody<Real>& xBody(const ContactArgs<Real>& a, int64_t i) {
    return a.body[2 * size_t(i)];
}

template <class Real>
__device__ inline PackedBody<Real>& vBody(const ContactArgs<Real>& a, int64_t i) {
    return a.body[2 * size_t(i) + 1];
}

}  // namespace corebox::gpu
