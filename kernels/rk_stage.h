// Stage arithmetic of the integrators, per particle, shared by the CPU loops and the CUDA kernels.
// Stage derivatives are stored stage-major: k[stage * n + i].
#pragma once

#include "butcher_tableau.h"
#include "hd.h"
#include "vec3.h"

namespace corebox {

// y0 + dt * sum_{j < count} w_j k_j for particle i. Zero weights are skipped: most of Hairer's and
// Dormand-Prince's entries are zero, and skipping them is exact.
template <class Real>
COREBOX_HD inline Vec3<Real> rkCombine(const double* weights, int count, Real dt, Vec3<Real> y0,
                                       const Vec3<Real>* k, size_t n, size_t i) {
    Vec3<Real> sum{0, 0, 0};
    for (int j = 0; j < count; ++j) {
        if (weights[j] != 0.0) sum += Real(weights[j]) * k[size_t(j) * n + i];
    }
    return y0 + dt * sum;
}

// Error-norm contribution of one component for the adaptive controller (Hairer, Norsett & Wanner,
// Solving ODEs I, II.4): (err / (atol + rtol * max(|y0|, |y1|)))^2, with atol = rtol = tol.
template <class Real>
COREBOX_HD inline double scaledErrorSquared(Real error, Real y0, Real y1, double tolerance) {
    const double scale = tolerance * (1.0 + fmax(fabs(double(y0)), fabs(double(y1))));
    const double e = double(error) / scale;
    return e * e;
}

// Step-size controller of the embedded pair (Hairer, Norsett & Wanner I, II.4, eq. 4.13): the next
// step is dt * 0.9 * err^(-1/(q+1)), limited to [0.2, 5] times the current one; a non-finite error
// shrinks by the lower limit.
COREBOX_HD inline double adaptiveStepFactor(double error, int embeddedOrder) {
    if (!(error == error) || error > 1e300) return 0.2;
    const double factor = 0.9 * pow(error > 1e-10 ? error : 1e-10, -1.0 / double(embeddedOrder + 1));
    return factor < 0.2 ? 0.2 : (factor > 5.0 ? 5.0 : factor);
}

// Velocity Verlet (kick-drift-kick): v += a dt/2; x += v dt; a = F(x)/m; v += a dt/2.
template <class Real>
COREBOX_HD inline void verletKick(Vec3<Real>& v, Vec3<Real> a, Real halfDt) { v += halfDt * a; }

template <class Real>
COREBOX_HD inline void verletDrift(Vec3<Real>& x, Vec3<Real> v, Real dt) { x += dt * v; }

}  // namespace corebox
