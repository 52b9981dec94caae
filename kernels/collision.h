// Hard-core collision rule and the straight-line rewind of the a posteriori resolution (report
// sec. 4, DESIGN.md sec. 2).
//
// After a step, a pair i,j with centre distance below d = a_i + a_j is rewound along its
// end-of-step velocities to the moment of contact. With r = r_i - r_j, v = v_i - v_j and the
// backward time s >= 0, |r - v s|^2 = d^2 gives a s^2 - 2 b s + c = 0 with a = |v|^2,
// b = r.v, c = |r|^2 - d^2 < 0 (overlap). The positive root (b + sqrt(b^2 - a c)) / a is
// rewritten as c / (b - sqrt(b^2 - a c)): for an approaching pair (b < 0) the denominator is a
// sum of two negative terms, so no cancellation even when a is tiny.
#pragma once

#include <cmath>

#include "hd.h"
#include "vec3.h"

namespace corebox {

// Backward time to contact, or a negative value when the pair is not approaching (b >= 0): such an
// overlap did not come from straight-line motion within the step and needs a positional fix.
template <class Real>
COREBOX_HD inline Real contactRewindTime(Vec3<Real> r, Vec3<Real> v, Real contactDistance) {
    const Real b = dot(r, v);
    if (b >= Real(0)) return Real(-1);
    const Real a = norm2(v);
    const Real c = norm2(r) - contactDistance * contactDistance;
    if (c >= Real(0)) return Real(0);
    const Real disc = b * b - a * c;  // > b^2 because a c < 0
    return c / (b - realSqrt(disc));
}

// Normal impulse magnitude J for a pair with normal relative speed vn = (v_i - v_j).n < 0:
//   J = -(1 + e) mu vn, mu = m_i m_j / (m_i + m_j); v_i += J n / m_i, v_j -= J n / m_j.
// The kinetic energy lost is (1 - e^2) mu vn^2 / 2.
template <class Real>
COREBOX_HD inline Real collisionImpulse(Real reducedMass, Real normalSpeed, Real restitution) {
    return -(Real(1) + restitution) * reducedMass * normalSpeed;
}

template <class Real>
COREBOX_HD inline Real collisionEnergyLoss(Real reducedMass, Real normalSpeed, Real restitution) {
    return Real(0.5) * (Real(1) - restitution * restitution) * reducedMass * normalSpeed * normalSpeed;
}

// Contacts slower than this are treated as elastic, so a chain of inelastic collisions cannot
// collapse into infinitely many events in finite time (inelastic collapse) and hang a step.
template <class Real>
COREBOX_HD inline Real effectiveRestitution(Real restitution, Real normalSpeed, Real elasticBelowSpeed) {
    return realAbs(normalSpeed) < elasticBelowSpeed ? Real(1) : restitution;
}

// Wall penetration on one axis: the centre must stay in [radius, boxLength - radius]. Returns the
// backward time to contact along the current velocity, or a negative value when the particle is
// moving away from the wall it penetrates (needs a positional fix), or 0-or-more when it does.
// side: 0 low wall, 1 high wall.
template <class Real>
COREBOX_HD inline Real wallRewindTime(Real position, Real velocity, Real radius, Real boxLength, int side) {
    if (side == 0) {
        const Real depth = radius - position;
        if (depth <= Real(0)) return Real(-2);  // no penetration
        return velocity < Real(0) ? depth / -velocity : Real(-1);
    }
    const Real depth = position - (boxLength - radius);
    if (depth <= Real(0)) return Real(-2);
    return velocity > Real(0) ? depth / velocity : Real(-1);
}

}  // namespace corebox

namespace corebox {

// Relative slack below which a distance counts as contact, not overlap: a pair put back exactly at
// contact must not be found overlapping again because of the last bit of rounding.
template <class Real>
COREBOX_HD inline Real contactSlack();
template <>
COREBOX_HD inline double contactSlack<double>() { return 1e-12; }
template <>
COREBOX_HD inline float contactSlack<float>() { return 2e-6f; }

}  // namespace corebox

namespace corebox {

// Second-order rewind. The integrator already applied the forces over the whole step, so a
// straight-line rewind reflects a velocity that kept accelerating after the contact: under a force
// F pressing a particle onto a wall it gains ~2 F v s of energy per hit (first order in dt). Rewinding
// along the parabola x(-s) = x - v s + a s^2 / 2 with the end-of-step acceleration a, colliding with
// the contact velocity v - a s and moving forward along the parabola again removes that error.

// Backward time to the wall along the parabola for the normal coordinate: p = x - wall (signed so
// that the penetration is p < 0 when v < 0 reaches the wall), v and a the normal velocity and
// acceleration. Solves (a/2) s^2 - v s + p = 0 for its smallest positive root in the stable form
// s = 2p / (v + sgn(v) sqrt(v^2 - 2 a p)); falls back to the straight line p / v. Never more than
// maxRewind (the step): the contact began within it.
template <class Real>
COREBOX_HD inline Real parabolicWallRewindTime(Real p, Real v, Real a, Real straightLine, Real maxRewind) {
    const Real disc = v * v - Real(2) * a * p;
    Real s = straightLine;
    const Real root = disc >= Real(0) ? realSqrt(disc) : Real(0);
    const Real denominator = v + (v < Real(0) ? -root : root);
    if (disc >= Real(0) && denominator != Real(0)) {
        const Real parabolic = Real(2) * p / denominator;
        if (parabolic >= Real(0)) s = parabolic;
    }
    return s < maxRewind ? s : maxRewind;
}

// Backward time to contact of a pair along the relative parabola r(-s) = r - v s + a s^2 / 2,
// refined by Newton from the straight-line time s0 (|r(-s)|^2 = d^2 is a quartic). Keeps s0 when
// Newton does not converge to a non-negative root nearby; never more than maxRewind (the step).
template <class Real>
COREBOX_HD inline Real parabolicContactRewindTime(Vec3<Real> r, Vec3<Real> v, Vec3<Real> a, Real d, Real s0, Real maxRewind) {
    Real s = s0;
    for (int it = 0; it < 4; ++it) {
        const Vec3<Real> rs = r - s * v + (Real(0.5) * s * s) * a;
        const Vec3<Real> drs = (s * a) - v;
        const Real f = norm2(rs) - d * d;
        const Real df = Real(2) * dot(rs, drs);
        if (df == Real(0)) return s0;
        s -= f / df;
    }
    const Real tolerance = Real(0.5) * s0 + Real(1e-12);
    const Real refined = (s >= Real(0) && realAbs(s - s0) <= tolerance) ? s : s0;
    return refined < maxRewind ? refined : maxRewind;
}

}  // namespace corebox
