// Lennard-Jones pair interaction with species mixing (report eq. 6):
//   U(R) = 4 eps_ij [ (sigma_ij/R)^12 - x_ij (sigma_ij/R)^6 ]
// x_ij scales the attraction only. An optional cutoff r_c truncates it with one of three shifts:
//   none   : U and F cut at r_c (both jump)
//   energy : U(R) - U(r_c)                    (F still jumps: fine for sampling, not for NVE)
//   force  : U(R) - U(r_c) - (R - r_c) U'(r_c) (U and F continuous: energy and convergence tests)
// The force loop works with R^2 only; the force-shifted form needs R itself, so only that mode
// pays for one sqrt per pair inside the cutoff.
#pragma once

#include <cmath>

#include "hd.h"

namespace corebox {

enum class CutoffShift : int { None = 0, Energy = 1, Force = 2 };

// Per species pair, precomputed once per parameter change (src/core/pair_table.cpp).
template <class Real>
struct PairCoefficients {
    Real sigma2 = 1;     // sigma_ij^2
    Real eps4 = 4;       // 4 eps_ij; 0 switches the pair force off (pure hard spheres)
    Real mixing = 1;     // x_ij
    Real cutoff2 = 0;    // r_c^2; 0 means all pairs interact
    Real energyShift = 0;  // subtracted from U inside the cutoff (energy and force shifts)
    Real forceAtCutoff = 0;  // -U'(r_c), used by the force shift
    Real cutoff = 0;     // r_c (force shift only)
    int shift = 0;       // CutoffShift
};

// Unshifted LJ energy and scalar force / R at squared distance r2: F_vec = fOverR * r_vec.
//   -dU/dR = (24 eps / R) [2 (s/R)^12 - x (s/R)^6], so F/R = (6 eps4 / R^2) s6 (2 s6 - x),
// written so the force costs one reciprocal and a handful of multiplies (the GPU inner loop).
// R = 0 (a particle with itself) gives zero force and energy without a branch; loops that know
// they never meet R = 0 (the GPU's off-diagonal tiles) skip even that select with kMayBeSelf.
template <class Real, bool kMayBeSelf = true>
COREBOX_HD inline Real ljForceOverR(Real sigma2, Real eps4, Real mixing, Real r2, Real* energy) {
    const Real inv2 = kMayBeSelf ? (r2 > Real(0) ? realReciprocal(r2) : Real(0)) : realReciprocal(r2);
    const Real s2 = sigma2 * inv2;
    const Real s6 = s2 * s2 * s2;
    if (energy) *energy = eps4 * s6 * (s6 - mixing);
    return (Real(6) * eps4 * inv2) * (s6 * realFma(Real(2), s6, -mixing));
}

// Shifts for a pair table entry; computed in double on the host, then stored in Real.
inline void computeCutoffShift(double sigma2, double eps4, double mixing, double cutoff, CutoffShift shift,
                               double* energyShift, double* forceAtCutoff) {
    *energyShift = 0;
    *forceAtCutoff = 0;
    if (cutoff <= 0 || shift == CutoffShift::None) return;
    double uc = 0;
    const double fOverR = ljForceOverR<double>(sigma2, eps4, mixing, cutoff * cutoff, &uc);
    *energyShift = uc;
    if (shift == CutoffShift::Force) *forceAtCutoff = fOverR * cutoff;
}

// Force on i from j divided by R (multiply by r_i - r_j) and, if energy != nullptr, the pair energy.
// Pairs beyond the cutoff contribute nothing. Every pair is computed and the result then kept or
// zeroed (keepOrZero): no branch on the distance, which a neighbour list (a third of its pairs beyond
// r_c in an LJ liquid) would mispredict on the CPU. A NaN distance counts as inside, so it propagates.
template <class Real>
COREBOX_HD inline Real pairForceOverR(const PairCoefficients<Real>& p, Real r2, Real* energy) {
    const bool cut = p.cutoff2 > Real(0);
    const bool inside = p.eps4 != Real(0) && !(cut && r2 >= p.cutoff2);
    Real u = 0;
    Real f = ljForceOverR(p.sigma2, p.eps4, p.mixing, r2, energy ? &u : nullptr);
    if (cut && p.shift == int(CutoffShift::Force)) {
        const Real r = realSqrt(r2);
        u += -p.energyShift + (r - p.cutoff) * p.forceAtCutoff;
        f -= p.forceAtCutoff / r;
    } else if (cut && p.shift == int(CutoffShift::Energy)) {
        u -= p.energyShift;
    }
    if (energy) *energy = keepOrZero(inside, u);
    return keepOrZero(inside, f);
}

}  // namespace corebox
