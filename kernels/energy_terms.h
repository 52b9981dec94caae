// One-particle energy terms shared by the backends' observables: kinetic m v^2 / 2 and the
// potential of uniform gravity, U = -m g.x (zero at the origin, so a ball resting on the floor at
// height a has U = m |g| a).
#pragma once

#include "hd.h"
#include "vec3.h"

namespace corebox {

COREBOX_HD inline double kineticEnergyOf(double mass, Vec3<double> v) { return 0.5 * mass * norm2(v); }

COREBOX_HD inline double gravityPotentialOf(double mass, Vec3<double> gravity, Vec3<double> x) { return -mass * dot(gravity, x); }

}  // namespace corebox
