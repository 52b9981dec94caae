// The particle instance layout: what a backend writes for the renderer to draw, defined once. Five
// floats per particle (centre, hard-core radius, colour key) in the order of the GL instance
// buffer's vertex attributes (src/render/particle_renderer.cpp). The CPU backend writes it into host
// memory, the CUDA backend straight into a mapped GL buffer (interop) or a host copy, both through
// particleInstanceOf, so the key is computed the same way everywhere.
#pragma once

#include <cstdint>

#include "hd.h"
#include "vec3.h"

namespace corebox {

struct ParticleInstance {
    float x, y, z;
    float radius;
    float colorKey;  // species index, or the speed |v| (InstanceKey::Speed)
};
static_assert(sizeof(ParticleInstance) == 5 * sizeof(float), "tightly packed: shared with GL and CUDA");

// What the colour key holds.
enum class InstanceKey { Species, Speed };

template <class Real>
COREBOX_HD inline ParticleInstance particleInstanceOf(Vec3<Real> x, Vec3<Real> v, int32_t species, Real radius, InstanceKey key) {
    const float colorKey = key == InstanceKey::Speed ? float(sqrt(double(norm2(v)))) : float(species);
    return ParticleInstance{float(x.x), float(x.y), float(x.z), float(radius), colorKey};
}

}  // namespace corebox
