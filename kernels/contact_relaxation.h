// Resting and dense contact: the second phase of the collision stage (DESIGN.md sec. 2), shared by
// the CPU backend and the CUDA kernels.
//
// Why a second phase. The a posteriori rounds of collision_resolution.h resolve impacts one
// matching at a time. In a pile every ball presses on its supports at every step: gravity moves the
// whole pile down by g dt^2 / 2 during the integration, every contact overlaps a little again, and
// the rounds must carry the support from the floor to the top one layer per round. A pile of 40
// layers needs more rounds per step than any cap allows, and a capped step leaves overlaps that the
// next step rewinds as if they were new collisions (energy from nowhere). So the stage is split:
//   1. impacts: contacts that began within this step (rewind time <= dt) and approach faster than
//      the resting speed (a few g dt) are collisions, resolved as before with restitution e;
//   2. contacts: every remaining overlapping pair and wall, and every resting one (touching and
//      approaching slower than the resting speed), is relaxed with restitution 0 over a contact list,
//      on two levels (below). The list is made again when deep overlaps moved particles into
//      neighbours it did not hold (collision_rounds.cpp).
// Slow contacts with e = 0 are what every rigid-body engine does below its restitution threshold,
// and what stops inelastic collapse; the elastic-below-speed rule of phase 1 still applies to
// impacts.
// One exception keeps restitution (ContactBounce): a contact that is the only one of both its
// particles and approaches faster than the resting speed. In an elastic hard-sphere fluid these are
// the impacts phase 1 cannot take: an earlier impact of the same step turned one of the pair, so
// the straight-line rewind of the new overlap runs past the step. Stopping them took kinetic energy
// out of a fluid that must keep it (1e-5 of it over 1,000 steps of the phi = 0.45 preset at
// dt = 0.002, every case an isolated pair; 1.5e-4 at dt = 0.004, two cases in 65 a pair of pairs).
// Newton's law on a single contact is exact and loses (1 - e^2) mu vn^2 / 2 >= 0, so it never adds
// energy. A contact in a cluster still stops: restitution applied to a contact network has no unique
// outcome and can add energy; stopping never does.
//
// The two levels of a contact:
//   - velocity: a contact approaching at normal speed vn < 0 is stopped (impulse -mu vn); each such
//     update alone removes kinetic energy mu vn^2 / 2; the core measures the kinetic energy before
//     and after the phase and books the difference as dissipated, exactly.
//   - position: an overlap is removed by moving the pair apart along the line of centres
//     (overlapShare: the heavier less; under gravity the upper one more, so one bottom-up pass lifts
//     a stack out of its supports); a wall pushes its particle out. Velocities are not changed by
//     this level (split impulse): removing an overlap never adds kinetic energy, and momentum is
//     untouched. The backend reports the work done against gravity by the moves (sum of -m g . dx)
//     and the core books it too, so E_kin + E_pot + E_dissipated stays exact.
// Two schedules of the same contact arithmetic:
//   - Gauss-Seidel (the CPU and the GPU): one contact at a time, with the latest values of both
//     particles and an accumulated impulse lambda >= 0 per contact (sequential impulses). The CPU
//     takes the contacts bottom-up against gravity, so support reaches the top of a pile within a
//     sweep; the GPU in colours (kernels/contact_gauss_seidel.cu: no particle has two contacts of a
//     colour, so a colour's contacts are updated together). The momentum of a deep pile reaches the
//     floor in few sweeps only over-relaxed (kGaussSeidelOverRelaxation), in either order.
//     Evidence for the GPU's switch from Jacobi (an H200, fp32, `corebox bench pile`, 5 s, the same
//     run with both): the 10^4-ball pile took 18.7 sweeps a step instead of 126 and 13.9 ms a frame
//     instead of 17.7, 10^5 balls 34 instead of 233 and 38.9 ms instead of 43.9, 10^6 balls 41
//     instead of 288 and 197 ms instead of 447; rest reached as early (3.25, 2.27, 2.27 s), overlaps
//     within 0.18% of a diameter, the conserved sum within 2.4e-6 (dissipation booked).
//   - Jacobi (the GPU's fallback, relaxParticle; CudaBackendOptions::gaussSeidelContacts = false, or a
//     listing needing more than 64 colours): each particle from the previous sweep's values only, with the
//     relaxation w = 1 / max(k_i, k_j) (k: listed contacts; mass splitting) so that the sum of a
//     particle's updates does not overshoot, and an accumulated impulse lambda >= 0 per contact held
//     in both particles' rows (the same value: the update is symmetric). The same result in any thread
//     order; it converges more slowly than Gauss-Seidel in deep piles (support climbs a layer per
//     sweep), which the warm start below makes up for in a resting pile, and the acceleration below
//     in part while the pile forms.
// Acceleration of the Jacobi sweeps. The velocity level is a bound-constrained quadratic program:
// minimise f(lambda) = lambda . J v + lambda . A lambda / 2 over lambda >= 0 (A = J M^-1 J^T), and
// f is the change of kinetic energy the impulses make. A Jacobi sweep with mass splitting is one
// projected gradient step of it, scaled per contact by w mu; its error shrinks by about 1 - 1/kappa
// a sweep, and kappa grows with the square of the pile's depth. Nesterov's extrapolation (the
// accelerated projected gradient that granular solvers on GPUs use) shrinks it by about
// 1 - 1/sqrt(kappa): each sweep starts from the applied impulses y = lambda_k + beta_k (lambda_k -
// lambda_{k-1}) (acceleratedImpulse, sweepMomentum), restarted at every listing. The velocities hold
// the applied impulses, which may pull (y < 0); where the host stops, endRelaxation moves every row
// to its projected impulse (settleRow), so the phase ends with lambda >= 0. Extrapolated sweeps are
// not monotone in f: the phase's change of kinetic energy is measured and booked as before, and the
// tests check that it never rises (tests/unit/test_contact_sweeps.cpp at every stopping point of a
// column, the dense-contact tests on random dense configurations). The positions are not
// extrapolated: their level only pushes, so an overshoot would stay (a 20-ball column lowered 2e-3
// into the floor came out up to 0.029 high).
// Evidence (an H200, fp32, `corebox bench pile`, 5 s, 128 sweeps a listing). Before, nearly every
// listing of a forming pile reached the sweep cap with its velocity level, not its positions, above
// tolerance (10^5 balls: 4997 of 4998 capped listings; 3367 of 3527 with a tolerance ten times
// looser). Accelerated, a column of 40 balls stops in 184 sweeps instead of 6600; the 10^5-ball pile
// takes 233 sweeps and 1.9 listings a step instead of 535 and 4.2, 51 ms a frame instead of 113 (30 ms
// in its last second), comes to rest at 2.2 s (before: not within 5 s) with overlaps within 0.04% of
// a diameter (before: 0.25%); 10^4 balls 20.5 ms instead of 24. Tried and not kept: averaging each
// particle's position moves over its overlapping contacts instead of w = 1 / max(k_i, k_j) (109
// against 112 ms); a plain sweep for the residual the host reads (the extrapolation dropped one sweep
// in eight, and the positions extrapolated too: 87 ms; the column 1504 sweeps); a cap of 64 sweeps without acceleration (65 ms, the pile
// not at rest within 5 s); listing again only from overlaps of 2% of a diameter (overlaps reached
// 2.4%).
// Which contacts are listed. Every overlapping pair and wall, and every touching one within the
// resting gap that is not approaching faster than the resting speed, separating ones included: an
// update never pulls (lambda >= 0), so a separating contact costs nothing unless the impulses of its
// neighbours turn it into an approach, and then it must be there. Listing only the approaching ones
// (as this code first did) missed exactly those: a settled pile's floor contacts stopped its bottom
// layer while the layers above, touching at zero relative speed and so unlisted, went on falling by
// g dt per step until they struck the layer below as impacts; a 10,000-ball pile then never came to
// rest (thousands of impacts and 64 rounds per step, a quarter of a diameter per second of mean
// downward speed, held up only by the position level).
// Warm start (both schedules). A resting pile bears the same weights step after step, so the impulses
// of the last step's relaxation are where this one ends: the first listing of a step starts each
// contact that was listed in the last step (same pair, or particle and wall) from its last lambda,
// applied to the velocities before the first sweep, and the sweeps correct it, taking back what is
// no longer needed (lambda >= 0; the residual counts take-backs as well as approaches, so a converged
// relaxation holds no push that separates). Bouncing contacts start from 0. Checkpoints carry the
// impulses (bit-identical restarts); setting the state or the model forgets them. A later listing of
// the same step (deep overlaps moved particles) starts each contact from its impulse so far in the
// step, already in the velocities and booked, so not applied again: lambda >= 0 then bounds the
// step's whole impulse, a push an earlier listing overdid can be taken back, and the next step starts
// from the whole of it. Started from 0, as this code first did, each listing could only push more and
// the next step began from the last listing's share alone; a pile 40 layers deep (4,444 balls on a
// 10 x 10 floor, CPU, fp64, 16 sweeps a listing) then kept 1,234 of kinetic energy at 4 s and 309 at
// 5 s (1.7 listings a step, the pile rattling), carried 62 and 36, in the same time. `corebox bench
// pile` on the CPU (fp64, 2 threads): 40,000 balls 741 ms a frame instead of 868 (the last second 503
// instead of 690), 1.8 listings a step instead of 1.96, the final overlap 0.014% of a diameter
// instead of 0.16%. On an H200 (fp32, the same call): 10^6 balls 139.1 ms a frame instead of 158.2
// (the last second 79.2 instead of 125.2; the settled pile's kinetic energy about 0.02 a ball instead
// of 0.2), 2.20 listings and 35 sweeps a step instead of 2.54 and 41; 10^5 balls 32.0 instead of 36.0
// (15.9 and 22.8), the final overlap 0.07% of a diameter instead of 0.32%.
// Tried and not kept: half of the warm start applied before the step's integration instead of after it
// (as a constant contact force over the step would act), so that a resting pile no longer falls by
// g dt^2 / 2 into its supports every step. The 10,000-ball pile on the CPU (fp64, 2 threads) ended with
// overlaps of 1e-12 of a diameter instead of 4.7e-5 and took 65 to 67 ms a frame over its last second
// instead of 93 to 97 (two runs each); on an H200 (fp32) 10^6 balls took 46.0 ms a frame against 47.3,
// overlaps 2.5e-5 against 5e-4, and the dense-contact tests' settled pile held even at 8 and 12 sweeps a
// listing. But a column of ten balls on the floor rose 7.4e-4 (CPU) and 8.7e-4 (H200) in 10^4 steps,
// where the tests allow 2e-4: a push carried ahead moves positions, and where it was more than the
// step needed the velocity level takes the impulse back but cannot pull the positions back.
// Evidence (2,000 balls dropped into a 30 x 60 x 30 box, e = 0.5, g = 9.81, dt = 1/240, 10 s):
// the old rounds alone hit their cap on most steps once the pile formed and failed at t = 4.6 s with
// a ball thrown out of the box; with the two phases the pile comes to rest (kinetic energy 3e-5 of
// the potential energy released) with the conserved sum within 6e-6 (CPU, fp64) and 1e-6 (H200,
// fp64 and fp32) of its start. With every touching contact listed and the warm start (`corebox bench
// pile`, 5 s, 4 steps a frame): 10,000 balls on the CPU (2 threads, fp64, 16 Gauss-Seidel sweeps) take
// 105 ms a frame against Bullet's 210 in the same run (before, on another 2-core machine: 606 against
// 286), overlaps within 0.03% of a diameter; on an H200 (fp32, Jacobi) 30 ms a frame (before: 36),
// 0.08%. With the resting speed at 6 g dt (collision_rounds.cpp: kRestingSteps) and the sweeps'
// residual taken once a warp (contact_kernels.cu): CPU fp64 89 ms a frame against Bullet's 211, H200
// 24 ms; 10^5 balls on the H200 113 ms a frame (before: 416), not yet at rest after 5 s, its contact
// phase three quarters of the time at about 535 Jacobi sweeps a step (the sweep cap, 128 a listing,
// over about four listings).
#pragma once

#include <cmath>
#include <cstdint>

#include "collision.h"
#include "hd.h"
#include "impulse_sums.h"
#include "vec3.h"

namespace corebox {

// A contact of particle i: another particle (partner >= 0) or a wall, -1 - (2 axis + side).
COREBOX_HD inline bool isWallContact(int64_t partner) { return partner < 0; }

// A contact's accumulated normal impulse at the end of a relaxation, kept for the next step's warm
// start: particle i, its partner (a higher index, or a wall code) and lambda (per unit mass for a
// wall) [mass sigma / tau].
struct ContactWarmStart {
    int64_t i;
    int64_t partner;
    double lambda;
};

// Whether a record read back (a checkpoint) can warm-start n particles: an index in range, a partner
// above it or a wall, and a finite push.
inline bool isUsableWarmStart(const ContactWarmStart& w, int64_t n) {
    return w.i >= 0 && w.i < n && w.partner < n && !(w.partner >= 0 && w.partner <= w.i) && w.partner >= -kWallCount &&
           std::isfinite(w.lambda) && w.lambda > 0;
}

// Adds `delta` to a contact's accumulated impulse, which never goes below 0 (a contact only pushes);
// returns the impulse actually applied.
template <class Real>
COREBOX_HD inline Real accumulateImpulse(Real& lambda, Real delta) {
    const Real next = lambda + delta > Real(0) ? lambda + delta : Real(0);
    const Real applied = next - lambda;
    lambda = next;
    return applied;
}

// The accelerated form of accumulateImpulse (Nesterov's projected gradient): `lambda` is the contact's
// last projected impulse, `applied` the extrapolated one the velocities hold. The projected step from
// the applied point, then the extrapolation beta (lambda_new - lambda_old); returns the change of the
// applied impulse. With beta = 0 the applied impulse is the projected one and this is
// accumulateImpulse from that point.
template <class Real>
COREBOX_HD inline Real acceleratedImpulse(Real& lambda, Real& applied, Real delta, Real beta) {
    const Real projected = applied + delta > Real(0) ? applied + delta : Real(0);
    const Real extrapolated = projected + beta * (projected - lambda);
    const Real change = extrapolated - applied;
    lambda = projected;
    applied = extrapolated;
    return change;
}

// The extrapolation of sweep k of a listing (k = 0 the first): Nesterov's (k - 1) / (k + 2), 0 for the
// first two. A listing starts afresh (the warm start is a point, not a direction); within it the
// momentum is never dropped, not even for the sweeps whose residual the host reads: one plain sweep
// in eight (the batch) made a column of 40 balls take 1504 sweeps to stop instead of 184 (plain
// Jacobi: 6600; tests/unit/test_contact_sweeps.cpp).
template <class Real>
COREBOX_HD inline Real sweepMomentum(int k) {
    return k < 2 ? Real(0) : Real(k - 1) / Real(k + 2);
}

// The mass terms of a pair contact's Gauss-Seidel updates, the same in every sweep: computed once (the
// CPU: per pair of species; the GPU: per row, for both levels), so that a sweep multiplies where it
// divided. With relaxPairContact's one line of centres a contact and noteLargestRatio, the CPU's pair
// update went from eight divisions and two square roots to two and one. It gained less than that
// suggests: the sandbox example at 2,000 balls (2-core EPYC, fp64, one world thread, two runs each)
// spent 6.8 ms a frame in its contact phase against 7.2, and `corebox bench pile --n 2000 --threads 1`
// 5.1 ms a frame in the sweeps of its settled pile as before: the sweeps wait on their chain of
// velocity updates more than on arithmetic.
template <class Real>
struct PairMasses {
    Real inverseI, inverseJ;  // 1 / m_i, 1 / m_j [1 / mass]
    Real mu;                  // the reduced mass m_i m_j / (m_i + m_j) [mass]
    Real shareJ;              // m_j / (m_i + m_j): i's share of an overlap with no gravity (overlapShare)
};

template <class Real>
COREBOX_HD inline PairMasses<Real> pairMassesOf(Real mi, Real mj) {
    return PairMasses<Real>{Real(1) / mi, Real(1) / mj, mi * mj / (mi + mj), mj / (mi + mj)};
}

// An impulse along n (from j to i) on a pair: i gains it, j loses it.
template <class Real>
COREBOX_HD inline void applyPairImpulse(Vec3<Real>& vi, Vec3<Real>& vj, const PairMasses<Real>& m, Vec3<Real> n,
                                        Real impulse) {
    vi += (impulse * m.inverseI) * n;
    vj -= (impulse * m.inverseJ) * n;
}

// Which touching (not overlapping) contacts rest: those approaching slower than `speed` (a few g dt)
// and closer than `gap` (what that speed closes in a step). Both 0 without gravity: then only
// overlaps are relaxed and every approach is left to the impacts, with its restitution.
template <class Real>
struct RestingContact {
    Real speed;
    Real gap;
};

// The overlap of a pair at centre distance `dist` beyond the contact slack of collision.h (> 0:
// overlapping; < 0: apart) [sigma]. Phase 1 sees the same slack.
template <class Real>
COREBOX_HD inline Real contactGap(Real d, Real dist) {
    return d * (Real(1) - contactSlack<Real>()) - dist;
}

// A listed contact is one the relaxation acts on: overlapping beyond the contact slack of
// collision.h (phase 1 sees the same), or resting. A faster touching approach is an impact of the
// next step, with its restitution; a centre beyond a wall plane has escaped (the health check reports
// it) and is not an overlap to smooth away.
template <class Real>
COREBOX_HD inline bool pairContactActive(Vec3<Real> xi, Vec3<Real> vi, Vec3<Real> xj, Vec3<Real> vj, Real d, RestingContact<Real> resting) {
    const Vec3<Real> r = xi - xj;
    const Real r2 = norm2(r);
    const Real reach = d + resting.gap;
    if (!(r2 < reach * reach)) return false;
    const Real dist = realSqrt(r2);
    const Real gap = contactGap(d, dist);
    if (gap > Real(0)) return true;
    const Real vn = dist > Real(0) ? dot(vi - vj, r) / dist : Real(0);
    return -vn < resting.speed;
}

// Distance from the wall plane (positive inside).
template <class Real>
COREBOX_HD inline Real wallClearance(Real position, Real radius, Real boxLength, int side) {
    return side == 0 ? position - radius : (boxLength - radius) - position;
}

// Penetration beyond the contact slack of collision.h (phase 1 sees the same).
template <class Real>
COREBOX_HD inline Real wallDepth(Real position, Real radius, Real boxLength, int side) {
    return -wallClearance(position, radius, boxLength, side) - contactSlack<Real>() * (radius > Real(1) ? radius : Real(1));
}

template <class Real>
COREBOX_HD inline bool wallContactActive(Real position, Real velocity, Real radius, Real boxLength, int side, RestingContact<Real> resting) {
    if (!(wallClearance(position, radius, boxLength, side) > -radius)) return false;  // escaped (or not finite)
    const Real depth = wallDepth(position, radius, boxLength, side);
    if (depth > Real(0)) return true;
    const Real vn = side == 0 ? velocity : -velocity;
    return -vn < resting.speed && -depth < resting.gap;
}

// Restitution in the contact phase (design note above): isolated contacts approaching faster than
// `speed` bounce; all others stop.
template <class Real>
struct ContactBounce {
    Real restitution;      // between particles
    Real wallRestitution;  // against the walls
    Real elasticBelow;     // effectiveRestitution's elastic-below speed
    Real speed;            // the resting speed: slower approaches stop
};

// The restitution a contact gets at approach speed vn < 0: e (or 1 below the elastic-below speed)
// when it is isolated and faster than the resting speed, else 0.
template <class Real>
COREBOX_HD inline Real contactRestitution(bool isolated, Real vn, Real e, ContactBounce<Real> bounce) {
    return isolated && -vn > bounce.speed ? effectiveRestitution(e, vn, bounce.elasticBelow) : Real(0);
}

// The normal speed an isolated contact's Gauss-Seidel update aims at, from its normal speed vn at the
// listing: e times its approach when it approaches faster than the resting speed (it bounces), else 0
// (it stops). The CPU's and the GPU's listings set it alike.
template <class Real>
COREBOX_HD inline Real isolatedContactTarget(Real vn, Real e, ContactBounce<Real> bounce) {
    return vn < Real(0) ? -contactRestitution(true, vn, e, bounce) * vn : Real(0);
}

// The largest approach speed and relative overlap a sweep saw: how far from converged it is.
template <class Real>
struct ContactResidual {
    // max over contacts of the normal-speed change an update made or asked for: the approach speed
    // it stopped or, for a warm-started contact (Gauss-Seidel), the push it took back [sigma / tau]
    Real speedChange;
    Real overlap;        // max over contacts of depth / contact distance (0 when none overlaps)
};

// The schedule of one listing's relaxation (collision_rounds.cpp), the same wherever it runs
// (Backend::relaxListing on the host, relaxListingKernel on the GPU): the first sweep alone (its overlap
// says whether the positions moved far enough to list again), then batches of `batch` sweeps, the
// residual checked at the end of each, until it is within both tolerances or the cap ran: `maxSweeps`,
// or `relistSweeps` where the first sweep's overlap is at least `relistOverlap` (the listing is listed
// again, and that listing's sweeps go on from where these leave the contacts).
struct RelaxationPlan {
    int maxSweeps = 1;
    int batch = 1;
    double speedTolerance = 0;    // [sigma / tau]
    double overlapTolerance = 0;  // fraction of a contact distance
    double relistOverlap = 1e300;  // fraction of a contact distance (never, by default)
    int relistSweeps = 1 << 30;
    COREBOX_HD bool converged(const ContactResidual<double>& r) const {
        return r.speedChange <= speedTolerance && r.overlap <= overlapTolerance;
    }
    // The sweeps at most, given the first sweep's overlap.
    COREBOX_HD int sweepCap(double firstOverlap) const {
        return firstOverlap >= relistOverlap && relistSweeps < maxSweeps ? relistSweeps : maxSweeps;
    }
    // Whether the residual is looked at after `done` sweeps, the first sweep having seen `firstOverlap`
    // (not read for the first): after the first, at each batch's end and at the cap.
    COREBOX_HD bool checkedAfter(int done, double firstOverlap) const {
        return done == 1 || (done - 1) % batch == 0 || done >= sweepCap(firstOverlap);
    }
    // Whether the relaxation goes on after a check that saw `last`, the first sweep having seen
    // `firstOverlap`.
    COREBOX_HD bool continuesAfter(int done, const ContactResidual<double>& last, double firstOverlap) const {
        return done < sweepCap(firstOverlap) && !converged(last);
    }
};

struct RelaxationOutcome {
    ContactResidual<double> first{0, 0};  // after the first sweep
    ContactResidual<double> last{0, 0};   // after the last
    int sweeps = 0;
};

// The unit vector against gravity, or 0 without gravity.
template <class Real>
COREBOX_HD inline Vec3<Real> upOf(Vec3<Real> gravity) {
    const Real g = realSqrt(norm2(gravity));
    return g > Real(0) ? (Real(-1) / g) * gravity : Vec3<Real>{0, 0, 0};
}

// The fraction of a pair's overlap that particle i takes when the pair is pushed apart along n (from
// j to i). Without gravity (up = 0) the heavier moves less, m_j / (m_i + m_j): the pair's centre of
// mass stays put. Under gravity a support holds: the share of the upper particle grows with how
// vertical the contact is, up to all of it for one particle resting on top of another, so one
// bottom-up sweep lifts a whole stack out of its supports (symmetric moves would push each support
// back down and need many sweeps per layer). The lift is work against gravity, which the backend
// reports and the core books.
template <class Real>
COREBOX_HD inline Real overlapShare(Real massShare, Vec3<Real> n, Vec3<Real> up) {
    const Real vertical = dot(n, up);  // > 0: i is above j
    if (vertical > Real(0)) return massShare + (Real(1) - massShare) * vertical;
    return massShare * (Real(1) + vertical);
}

// Velocity and position changes of particle i from one Jacobi sweep over its listed contacts.
// `partner(c)` gives its c-th contact; `contactsOf(j)` the contact count k_j of particle j (k_i =
// count); `lambda[c]` the c-th contact's accumulated impulse (per unit mass for a wall), updated in
// place: only particle i's thread touches its row, and particle j's row holds the same value for the
// pair, computed from the same previous-sweep values (w, mu and vn are symmetric in i and j, bit for
// bit). Each update moves the contact's accumulated impulse towards stopping it, never below 0, with
// the splitting w = 1 / max(k_i, k_j): an approach is stopped, a push no longer needed is taken back.
// The sweeps are accelerated (acceleratedImpulse): `applied[c]` is the extrapolated impulse the
// velocities hold, moved by `beta` (sweepMomentum) past the projected one in lambda[c]; beta = 0 is
// the plain Jacobi sweep from the applied point.
// An isolated contact (the only one of both particles) approaching faster than the resting speed
// bounces with its restitution instead (contactRestitution), in one update. Adds the sweep's impulses
// to `given` (impulse_sums.h): the momentum each wall received from i, and half of r_ij . J_ij of each
// pair (j computes the same impulse, opposite, from its side: the sum over particles counts each pair
// impulse once).
template <class Real, class Partner, class ContactsOf, class Given>
COREBOX_HD inline void relaxParticle(int64_t i, int count, Partner&& partner, ContactsOf&& contactsOf, Real* lambda, const Vec3<Real>* x,
                                     const Vec3<Real>* v, const int32_t* species, const Real* mass, const Real* radius, Vec3<Real> box,
                                     Vec3<Real> up, ContactBounce<Real> bounce, Vec3<Real>& dv, Vec3<Real>& dx, ContactResidual<Real>& residual,
                                     Given& given, Real* applied, Real beta) {
    const Vec3<Real> xi = x[i], vi = v[i];
    const int si = species[i];
    const Real mi = mass[si], ai = radius[si];
    dv = Vec3<Real>{0, 0, 0};
    dx = Vec3<Real>{0, 0, 0};
    for (int c = 0; c < count; ++c) {
        const int64_t j = partner(c);
        if (isWallContact(j)) {
            const int code = int(-1 - j), axis = code / 2, side = code % 2;
            const Real w = Real(1) / Real(count);
            const Real inward = side == 0 ? Real(1) : Real(-1);  // the wall's normal, into the box
            const Real vn = inward * vi[axis];
            const Real e = vn < Real(0) ? contactRestitution(count == 1, vn, bounce.wallRestitution, bounce) : Real(0);
            Real push = 0;  // per unit mass
            if (e > Real(0)) {
                push = -(Real(1) + e) * vn;
            } else {
                push = acceleratedImpulse(lambda[c], applied[c], -w * vn, beta);
            }
            if (push != Real(0)) {
                dv[axis] += push * inward;
                given.addWall(code, double(mi) * double(push), atWallCentre(xi, ai, box, axis));
            }
            const Real change = (push < Real(0) ? -push : push) / w;
            if (change > residual.speedChange) residual.speedChange = change;
            const Real depth = wallDepth(xi[axis], ai, box[axis], side);
            if (depth > Real(0)) {
                dx[axis] += w * depth * inward;
                if (depth / (Real(2) * ai) > residual.overlap) residual.overlap = depth / (Real(2) * ai);
            }
            continue;
        }
        const int sj = species[j];
        const Real mj = mass[sj], d = ai + radius[sj];
        const Vec3<Real> r = xi - x[j];
        const Real dist = realSqrt(norm2(r));
        if (!(dist > Real(0))) continue;  // coincident centres carry no direction
        const Vec3<Real> n = (Real(1) / dist) * r;
        const int kj = contactsOf(j);
        const Real w = Real(1) / Real(count > kj ? count : kj);
        const Real vn = dot(vi - v[j], n);
        const PairMasses<Real> masses = pairMassesOf(mi, mj);
        const Real mu = masses.mu;
        const Real e = vn < Real(0) ? contactRestitution(count == 1 && kj == 1, vn, bounce.restitution, bounce) : Real(0);
        Real impulse = 0;
        if (e > Real(0)) {
            impulse = -(Real(1) + e) * mu * vn;
        } else {
            impulse = acceleratedImpulse(lambda[c], applied[c], -w * mu * vn, beta);
        }
        if (impulse != Real(0)) {
            dv += (impulse / mi) * n;
            given.pairVirial += 0.5 * double(dist) * double(impulse);
        }
        const Real change = (impulse < Real(0) ? -impulse : impulse) / (w * mu);
        if (change > residual.speedChange) residual.speedChange = change;
        const Real gap = contactGap(d, dist);
        if (gap > Real(0)) {
            dx += (w * gap * overlapShare(masses.shareJ, n, up)) * n;
            if (gap / d > residual.overlap) residual.overlap = gap / d;
        }
    }
}

// The velocity change of particle i from an impulse on each of its rows (Jacobi), `impulse(c)` along
// the row's line of centres (per unit mass for a wall), added to `given` as the sweeps' are: the warm
// start (the impulses lambda[c] its contacts begin with) and the end of the accelerated sweeps
// (settleRow: from the applied impulses to the projected ones).
template <class Real, class Partner, class Impulse>
COREBOX_HD inline Vec3<Real> rowImpulsesOf(int64_t i, int count, Partner&& partner, Impulse&& impulse, const Vec3<Real>* x,
                                           const int32_t* species, const Real* mass, const Real* radius, Vec3<Real> box,
                                           ImpulseSums& given) {
    const Vec3<Real> xi = x[i];
    const int si = species[i];
    const Real mi = mass[si], ai = radius[si];
    Vec3<Real> dv{0, 0, 0};
    for (int c = 0; c < count; ++c) {
        const Real j_c = impulse(c);
        if (j_c == Real(0)) continue;
        const int64_t j = partner(c);
        if (isWallContact(j)) {
            const int code = int(-1 - j), axis = code / 2;
            dv[axis] += code % 2 == 0 ? j_c : -j_c;
            given.addWall(code, double(mi) * double(j_c), atWallCentre(xi, ai, box, axis));
            continue;
        }
        const Vec3<Real> r = xi - x[j];
        const Real dist = realSqrt(norm2(r));
        if (!(dist > Real(0))) continue;
        dv += (j_c / mi) * ((Real(1) / dist) * r);
        given.pairVirial += 0.5 * double(dist) * double(j_c);
    }
    return dv;
}

// The impulse that takes a row from its applied (extrapolated) impulse to its projected one, which it
// then holds: where the accelerated sweeps stop, the velocities hold lambda >= 0.
template <class Real>
COREBOX_HD inline Real settleRow(const Real& lambda, Real& applied) {
    const Real change = lambda - applied;
    applied = lambda;
    return change;
}

// ---- Gauss-Seidel form (the CPU's schedule): one contact at a time, in a fixed order ----
//
// The same two levels as relaxParticle, applied to one contact with the latest values of both
// particles, so support travels from the floor to the top of a pile within one sweep when contacts
// are ordered bottom-up. The velocity level keeps the contact's accumulated impulse lambda >= 0
// (sequential impulses): an update may take back part of an earlier push, never pull; every update
// moves vn towards the contact's target separation speed: 0 (stop: each update removes kinetic
// energy), or for an isolated bouncing contact e times its approach speed at the listing
// (contactRestitution), reached by its first update and then held.

// Over-relaxation of the Gauss-Seidel velocity level (projected SOR). Every stopping update goes
// omega times the way to vn = 0 (then lambda >= 0 is enforced): a column of k balls pressed into the
// floor hands its momentum down about a layer per sweep at omega = 1, so the work grows with k^2 and a
// capped relaxation leaves the column moving down, faster with height; over-relaxed, the error shrinks
// about k times faster. It adds no kinetic energy at any stopping point: along one contact's impulse
// the kinetic energy is a convex parabola with its minimum at vn = 0, a step of omega in (0, 2) times
// the way to it lowers the energy by omega (2 - omega) / 2 of what the full step would, and the
// clamp to lambda = 0 lands between the start and the over-relaxed point, no higher than the start.
// Bouncing targets (an isolated contact aiming at e times its approach) are reached exactly (omega
// 1): over-relaxed, one update would send the pair apart faster than it came.
// Evidence (CPU, fp64, 2 threads, dt = 1/240, 16 sweeps a listing): 4,444 balls on a 10 x 10 floor
// (40 layers, as deep as the 40,000-ball pile): at omega = 1 the kinetic energy stays at 5% of the
// potential energy released from 2.5 s to 6 s (the top moving down at 6 sigma/tau, held up only by
// the position level); 1.6: 0.8% at 6 s; 1.8: 3.0e-3 at 3 s, 6.5e-5 at 6 s; 1.9: 0.16% (it
// oscillates). `corebox bench pile` (Bullet in the same run): the 40,000-ball pile at rest at 2.25 s
// (before: not within 8 s), 842 ms a frame against 1937 before; 10,000 balls at rest at 3.25 s as
// before, 114 ms a frame (Bullet 279).
constexpr double kGaussSeidelOverRelaxation = 1.8;

template <class Real>
COREBOX_HD inline Real stepFactor(Real target, Real omega) {
    return target == Real(0) ? omega : Real(1);
}

// Joins value / scale (scale > 0) to `largest`, the residual's largest so far. Most updates of a sweep
// are below it: their division is skipped where value is plainly below largest * scale (a margin of 1%
// against rounding: the largest is the same bits as dividing every one, but where largest * scale is
// subnormal).
template <class Real>
COREBOX_HD inline void noteLargestRatio(Real& largest, Real value, Real scale) {
    if (!(value > Real(0.99) * (largest * scale))) return;
    const Real ratio = value / scale;
    if (ratio > largest) largest = ratio;
}

// Moves the normal speed of particles i, j along n (from j to i) towards `target` >= 0 as far as
// lambda >= 0 allows, over-relaxed by `omega` when the target is 0 (stepFactor).
template <class Real>
COREBOX_HD inline void stopPairContact(Vec3<Real>& vi, Vec3<Real>& vj, const PairMasses<Real>& m, Vec3<Real> n,
                                       Real target, Real& lambda, ContactResidual<Real>& residual, Real omega) {
    const Real vn = dot(vi - vj, n);
    const Real impulse = accumulateImpulse(lambda, stepFactor(target, omega) * m.mu * (target - vn));
    noteLargestRatio(residual.speedChange, impulse < Real(0) ? -impulse : impulse, m.mu);
    applyPairImpulse(vi, vj, m, n, impulse);
}

// The same against a wall with inward normal `inward` (+1 low wall, -1 high wall) on `axis`.
template <class Real>
COREBOX_HD inline void stopWallContact(Real& v, Real inward, Real target, Real& lambda, ContactResidual<Real>& residual, Real omega) {
    const Real vn = inward * v;
    const Real push = accumulateImpulse(lambda, stepFactor(target, omega) * (target - vn));  // impulse per unit mass
    const Real change = push < Real(0) ? -push : push;
    if (change > residual.speedChange) residual.speedChange = change;
    v += push * inward;
}

// One wall contact's Gauss-Seidel update, the CPU's sweeps as the GPU's rows: the velocity level
// (stopWallContact, `side` 0 the low wall), then the position level (the particle pushed out by its
// depth beyond the contact slack). `x` and `v` are the particle's coordinate and velocity on the wall's
// axis; returns whether the position moved.
template <class Real>
COREBOX_HD inline bool relaxWallContact(Real& x, Real& v, int side, Real radius, Real boxLength, Real target,
                                        Real& lambda, ContactResidual<Real>& residual, Real omega) {
    const Real inward = side == 0 ? Real(1) : Real(-1);
    stopWallContact(v, inward, target, lambda, residual, omega);
    const Real depth = wallDepth(x, radius, boxLength, side);
    if (!(depth > Real(0))) return false;
    noteLargestRatio(residual.overlap, depth, Real(2) * radius);
    x += inward * depth;
    return true;
}

// One pair contact's Gauss-Seidel update on one line of centres: the velocity level (stopPairContact),
// then the position level (the overlap beyond the contact slack removed, shared as overlapShare says).
// Both levels of a contact at once, the CPU's sweeps as the GPU's rows: the velocity level moves no
// position, so the position level's line of centres is the one the velocity level used. (The CPU took
// the levels in two passes over the contacts, the second computing every line again; the pile tests
// and `corebox bench pile` settle as before either way.) Coincident centres carry no direction:
// nothing is updated. Returns whether the positions moved.
template <class Real>
COREBOX_HD inline bool relaxPairContact(Vec3<Real>& xi, Vec3<Real>& xj, Vec3<Real>& vi, Vec3<Real>& vj,
                                        const PairMasses<Real>& m, Real d, Vec3<Real> up, Real target, Real& lambda,
                                        ContactResidual<Real>& residual, Real omega) {
    const Vec3<Real> r = xi - xj;
    const Real dist = realSqrt(norm2(r));
    if (!(dist > Real(0))) return false;
    const Vec3<Real> n = (Real(1) / dist) * r;
    stopPairContact(vi, vj, m, n, target, lambda, residual, omega);
    const Real gap = contactGap(d, dist);
    if (!(gap > Real(0))) return false;
    noteLargestRatio(residual.overlap, gap, d);
    const Real share = overlapShare(m.shareJ, n, up);
    xi += (gap * share) * n;
    xj -= (gap * (Real(1) - share)) * n;
    return true;
}

}  // namespace corebox
