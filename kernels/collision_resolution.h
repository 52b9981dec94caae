// The a posteriori impacts step by step, shared by the CPU backend and the CUDA kernels (DESIGN.md
// sec. 2): the candidate events of a particle, the order that picks its earliest one, and the
// resolution of a pair or wall event along the second-order (parabolic) rewind of collision.h.
//
// In each parallel round every particle finds its earliest event among its overlaps; an event is
// resolved when it is the earliest event of every particle it touches. Those events form a matching,
// so they can be resolved concurrently without two threads writing one particle.
//
// An overlap is an impact of this step only when the straight-line rewind to contact is within the
// step (s <= dt: the contact began during this step) and the pair approaches faster than the resting
// speed. Anything else (an overlap inherited from an earlier step or handed in, a pair separating
// while overlapping, a slow contact pressed by gravity) is left to the contact relaxation of
// contact_relaxation.h: rewinding it further than the step would move it along a parabola it never
// followed and throw it forward with energy from nowhere.
#pragma once

#include <cfloat>
#include <cstdint>

#include "collision.h"
#include "hd.h"
#include "vec3.h"

namespace corebox {

// One candidate event of a particle. Larger key = earlier in the step (longer rewind). partner:
// particle index, or a wall code -1 - (2 * axis + side).
struct CollisionEvent {
    double key;
    int64_t partner;
};

constexpr int64_t kNoPartner = INT64_MIN;

enum CollisionKind : int { kNoCollision = 0, kPairCollision = 1, kWallCollision = 2 };

// Which overlaps count as impacts of this step: rewound at most maxRewind (the step) and approaching
// at least restingSpeed.
template <class Real>
struct ImpactWindow {
    Real maxRewind;
    Real restingSpeed;
};

// How one resolved impact went, for the contact log (backend.h ContactRecord, the library's contacts):
// the rewind from the end of the step to contact, the unit normal at contact (from j to i for a pair,
// into the box for a wall), the normal impulse given to i (to the particle, for a wall) including
// a resting-contact stop after the rebound, and the normal approach speed at contact.
template <class Real>
struct ImpactDetail {
    Real rewind;
    Vec3<Real> normal;
    Real impulse;
    Real speed;
};

// Whether the contact log keeps an impact (Backend::setContactLog): its impulse magnitude, compared in
// double, at least minImpulse.
template <class Real>
COREBOX_HD inline bool loggedImpact(const ImpactDetail<Real>& d, double minImpulse) {
    return !(double(d.impulse < Real(0) ? -d.impulse : d.impulse) < minImpulse);
}

// The margin of the impact rounds' candidate lists (the CPU's of a dense step, the GPU's rows, gpu_launch.h
// CandidateRows) beyond each pair's contact distance, as a fraction of a diameter (the CPU's largest, the
// GPU's largest in its cells): wider lists are longer to read, narrower ones are made again more often.
// The same events at any margin (the same state hashes and piles); on the CPU (a 2-core machine, fp32,
// `corebox bench pile --bullet none` 2,000 / 10,000 balls with 0.1 / 0.2 / 0.3 / 0.4 / 0.6): 5.6 / 4.3 /
// 4.0 / 4.6 / 3.6 and 63.9 / 56.9 / 55.0 / 54.5 / 54.3 ms a frame; the sandbox example (2,000 balls and a
// heavy one, whose diameter sets the CPU's margin) 3.38 / 2.8 / 2.6 / 2.45 ms of impact rounds a frame from
// 0.1 to 0.4. Not wider than 0.3: a row holds a fixed number of candidates, and a particle with more walks
// its cells again (at 1.6 diameters dense packings reach the second shell).
constexpr double kCandidateMargin = 0.3;

COREBOX_HD inline CollisionEvent noEvent() { return CollisionEvent{-DBL_MAX, kNoPartner}; }
COREBOX_HD inline bool isValid(const CollisionEvent& e) { return e.partner != kNoPartner; }
// Deterministic order: earlier event first, then the lower partner code.
COREBOX_HD inline bool isBetter(const CollisionEvent& a, const CollisionEvent& b) {
    return a.key > b.key || (a.key == b.key && a.partner < b.partner);
}
COREBOX_HD inline int64_t wallCode(int axis, int side) { return -1 - (2 * axis + side); }

// The rewind time of the pair (i, j)'s impact of this step (its event's key), or -1 where the two do not
// overlap in one. The same bits for (j, i): every term is a sum of products of two differences that
// both change sign (and a fused multiply-add of two negated factors is the same as of the factors).
template <class Real>
COREBOX_HD inline Real pairImpactRewind(Vec3<Real> xi, Vec3<Real> vi, Real ai, Vec3<Real> xj, Vec3<Real> vj, Real aj,
                                        ImpactWindow<Real> window) {
    const Real d = ai + aj;
    const Vec3<Real> r = xi - xj;
    const Real r2 = norm2(r);
    if (r2 >= d * d * (Real(1) - contactSlack<Real>())) return Real(-1);
    const Vec3<Real> v = vi - vj;
    const Real s = contactRewindTime(r, v, d);
    if (s < Real(0) || s > window.maxRewind) return Real(-1);  // separating, or not begun within this step
    const Real vn = dot(r, v);                                 // |r| times the normal speed, < 0 here
    if (vn * vn < window.restingSpeed * window.restingSpeed * r2) return Real(-1);  // a resting contact
    return s;
}

// Whether a particle starts a stage's impact rounds active: whether it could be in an impact of this
// step at all. A pair impact approaches faster than the resting speed, and its normal speed is at
// most |v_i| + |v_j|, so one of the two moves at least half of it; a wall impact needs the resting
// speed itself. Two slower particles can have no impact with each other (and none with a wall), so
// the first round finds the same events with only the movers active (an inactive particle looks at
// its active neighbours only): a settled pile's first search walks its few rattling balls instead of
// every ball. The margin (0.49 against 0.5) keeps rounding on the safe side. Without gravity the
// resting speed is 0 and every particle moves.
template <class Real>
COREBOX_HD inline bool startsActive(Vec3<Real> v, Real restingSpeed) {
    const Real least = Real(0.49) * restingSpeed;
    return !(norm2(v) < least * least);
}

// Offers the pair (i, j) to i's best event when the two overlap in an impact of this step.
template <class Real>
COREBOX_HD inline void considerPair(Vec3<Real> xi, Vec3<Real> vi, Real ai, Vec3<Real> xj, Vec3<Real> vj, Real aj,
                                    int64_t j, ImpactWindow<Real> window, CollisionEvent& best) {
    const Real s = pairImpactRewind(xi, vi, ai, xj, vj, aj, window);
    if (!(s >= Real(0))) return;  // none (a rewind that is not a number never was the earliest either)
    const CollisionEvent e{double(s), j};
    if (isBetter(e, best)) best = e;
}

// Offers every wall the particle has hit within this step to its best event.
template <class Real>
COREBOX_HD inline void considerWalls(Vec3<Real> x, Vec3<Real> v, Real radius, Vec3<Real> box, ImpactWindow<Real> window,
                                     CollisionEvent& best) {
    const Real slack = contactSlack<Real>() * (radius > Real(1) ? radius : Real(1));
    for (int axis = 0; axis < 3; ++axis) {
        for (int side = 0; side < 2; ++side) {
            const Real pos = side == 0 ? x[axis] + slack : x[axis] - slack;
            const Real s = wallRewindTime(pos, v[axis], radius, box[axis], side);
            if (s < Real(0) || s > window.maxRewind || realAbs(v[axis]) < window.restingSpeed) continue;
            const CollisionEvent e{double(s), wallCode(axis, side)};
            if (isBetter(e, best)) best = e;
        }
    }
}

// Resolves the pair event of i and j (key from i's event); a_i, a_j are their end-of-step
// accelerations. Adds the kinetic energy lost to *loss and r_ij . J_ij of the impulses applied to
// *virial (impulse_sums.h), and returns the CollisionKind.
template <class Real>
COREBOX_HD inline int resolvePairEvent(Vec3<Real>& xi, Vec3<Real>& vi, Vec3<Real> ai, Real mi, Vec3<Real>& xj, Vec3<Real>& vj,
                                       Vec3<Real> aj, Real mj, Real d, double key, Real maxRewind, Real e, Real elasticBelow,
                                       double* loss, double* virial, ImpactDetail<Real>* detail = nullptr) {
    const Real mu = mi * mj / (mi + mj);
    // Refined along the parabola, still bounded by the step (the key is the straight-line time).
    const Real s = parabolicContactRewindTime(xi - xj, vi - vj, ai - aj, d, Real(key), maxRewind);
    const Real halfS2 = Real(0.5) * s * s;
    xi += halfS2 * ai - s * vi;  // back to contact along each parabola
    xj += halfS2 * aj - s * vj;
    vi -= s * ai;
    vj -= s * aj;
    const Vec3<Real> r = xi - xj;
    const Real dist = realSqrt(norm2(r));
    const Vec3<Real> n = (Real(1) / dist) * r;
    const Real vn = dot(vi - vj, n);
    if (detail) *detail = ImpactDetail<Real>{s, n, Real(0), vn < Real(0) ? -vn : Real(0)};
    if (vn < Real(0)) {
        const Real eEff = effectiveRestitution(e, vn, elasticBelow);
        const Real impulse = collisionImpulse(mu, vn, eEff);
        vi += (impulse / mi) * n;
        vj -= (impulse / mj) * n;
        *loss += double(collisionEnergyLoss(mu, vn, eEff));
        *virial += double(dist) * double(impulse);  // J_ij = impulse n, r_ij = dist n
        if (detail) detail->impulse += impulse;
    }
    xi += s * vi + halfS2 * ai;  // and forward to the end of the step
    xj += s * vj + halfS2 * aj;
    vi += s * ai;
    vj += s * aj;
    // Resting contact: when the relative acceleration presses the pair together faster than the
    // rebound separates it, they end the step still overlapping. Put them at contact and remove the
    // closing normal velocity instead of colliding again. The energy this takes out (kinetic, minus
    // the work of lifting the pair apart against the pressing force, to first order in the small
    // gap) is counted as dissipated, so the balance stays exact.
    const Vec3<Real> rEnd = xi - xj;
    const Real distEnd = realSqrt(norm2(rEnd));
    if (distEnd < d * (Real(1) - contactSlack<Real>())) {
        const Vec3<Real> nEnd = distEnd > Real(0) ? (Real(1) / distEnd) * rEnd : n;
        const Real gap = d - distEnd;
        xi += (gap * mj / (mi + mj)) * nEnd;
        xj -= (gap * mi / (mi + mj)) * nEnd;
        *loss += double(mu * dot(ai - aj, nEnd) * gap);
        const Real closing = dot(vi - vj, nEnd);
        if (closing < Real(0)) {
            const Real impulse = collisionImpulse(mu, closing, Real(0));
            vi += (impulse / mi) * nEnd;
            vj -= (impulse / mj) * nEnd;
            *loss += double(collisionEnergyLoss(mu, closing, Real(0)));
            *virial += double(dot(xi - xj, nEnd)) * double(impulse);
            if (detail) detail->impulse += impulse;
        }
    }
    return kPairCollision;
}

// Resolves a wall event on one axis: x, v, a are that axis' components of the particle. Adds the
// momentum the wall received (along its outward normal, impulse_sums.h) to *wallImpulse.
template <class Real>
COREBOX_HD inline int resolveWallEvent(Real& x, Real& v, Real a, Real mass, Real radius, Real boxLength, int side, double key,
                                       Real maxRewind, Real e, Real elasticBelow, double* loss, double* wallImpulse,
                                       ImpactDetail<Real>* detail = nullptr) {
    const Real wall = side == 0 ? radius : boxLength - radius;
    // Normal coordinate pointing into the box: p = distance from the wall plane.
    const Real sign = side == 0 ? Real(1) : Real(-1);
    const Real p = sign * (x - wall);
    const Real vIn = sign * v;
    const Real aIn = sign * a;
    const Real s = parabolicWallRewindTime(p, vIn, aIn, Real(key), maxRewind);
    const Real vContact = vIn - aIn * s;
    const Real eEff = effectiveRestitution(e, vContact, elasticBelow);
    const Real vOut = vContact < Real(0) ? -eEff * vContact : vContact;
    if (detail) detail->impulse = Real(0);
    if (vContact < Real(0)) {
        *loss += double(collisionEnergyLoss(mass, vContact, eEff));
        *wallImpulse += double(mass) * (double(vOut) - double(vContact));
        if (detail) detail->impulse = mass * (vOut - vContact);
    }
    // Where the rewind stopped at its bound short of the wall (a penetration older than the step: the
    // straight-line time fits the window, the parabola's does not), the particle turns where the
    // rewind left it, still inside, and moves on from there; turning it at the wall plane instead lifted
    // it unbooked (a 400-ball pile gained 7.7e-4 of its 47,550 in one step, m g times the depth left).
    const Real pRewound = p - vIn * s + Real(0.5) * aIn * s * s;
    const Real pTurn = s >= maxRewind && pRewound < Real(0) ? pRewound : Real(0);
    Real pEnd = pTurn + vOut * s + Real(0.5) * aIn * s * s;
    Real vEnd = vOut + aIn * s;
    if (pEnd < Real(0)) {
        // Resting contact: pressed onto the wall harder than it rebounds. It stays on the wall and
        // an inward normal velocity is absorbed. Dissipated: that kinetic energy minus the work of
        // lifting it by -pEnd against the pressing acceleration.
        *loss -= double(mass * aIn * pEnd);
        pEnd = 0;
        if (vEnd < Real(0)) {
            *loss += double(Real(0.5) * mass * vEnd * vEnd);
            *wallImpulse -= double(mass) * double(vEnd);
            if (detail) detail->impulse -= mass * vEnd;
            vEnd = 0;
        }
    }
    x = wall + sign * pEnd;
    v = sign * vEnd;
    if (detail) {
        detail->rewind = s;
        detail->speed = vContact < Real(0) ? -vContact : Real(0);
        // The normal along this wall's axis is filled by the caller, which knows the axis.
        detail->normal = Vec3<Real>{Real(0), Real(0), Real(0)};
    }
    return kWallCollision;
}

}  // namespace corebox
