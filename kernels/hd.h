// Annotation shared by every physics header: the same function compiles for the CPU backend
// (plain C++) and for CUDA kernels (__host__ __device__). Keeping one definition of each formula
// means a CPU/GPU mismatch is a scheduling or precision bug, never a formula bug.
#pragma once

#if defined(__CUDACC__)
#define COREBOX_HD __host__ __device__
#else
#define COREBOX_HD
#endif

#include <cmath>

namespace corebox {

// Precision-preserving math for templates over float and double: std::sqrt(float) stays in float
// on the host and on the device (an unqualified sqrt may promote to double on the host).
template <class Real>
COREBOX_HD inline Real realSqrt(Real x) {
    return std::sqrt(x);
}
template <class Real>
COREBOX_HD inline Real realAbs(Real x) {
    return std::fabs(x);
}

// keep ? value : 0 without a branch: the device selects (one instruction); on the host a compiler
// may turn the select into a jump, which costs a misprediction when `keep` follows no pattern (a
// neighbour list's pairs inside and beyond the cutoff), so it multiplies by 0 or 1 instead (exact for
// a finite value; a zero may come out as -0, which adds to any sum as +0 does).
template <class Real>
COREBOX_HD inline Real keepOrZero(bool keep, Real value) {
#if defined(__CUDA_ARCH__)
    return keep ? value : Real(0);
#else
    return value * Real(keep);
#endif
}

// a * b + c as one fused operation on the device (one instruction in the force loop); the host
// keeps the plain expression, since std::fma is a slow library call without hardware FMA flags.
template <class Real>
COREBOX_HD inline Real realFma(Real a, Real b, Real c) {
#if defined(__CUDA_ARCH__)
    return fma(a, b, c);
#else
    return a * b + c;
#endif
}

// 1/x for x > 0: the host divides; the device uses the hardware reciprocal estimate in float (one
// instruction, within an ulp: the float force loop tolerates that, see the fp32 conformance test)
// and, in double, two Newton steps from it (within an ulp or two of 1/x at a fraction of the cost
// of a double division, which would otherwise dominate the LJ inner loop).
COREBOX_HD inline float realReciprocal(float x) {
#if defined(__CUDA_ARCH__)
    float r;
    asm("rcp.approx.ftz.f32 %0, %1;" : "=f"(r) : "f"(x));
    return r;
#else
    return 1.0f / x;
#endif
}
COREBOX_HD inline double realReciprocal(double x) {
#if defined(__CUDA_ARCH__)
    double r = double(realReciprocal(float(x)));
    r = r * (2.0 - x * r);
    return r * (2.0 - x * r);
#else
    return 1.0 / x;
#endif
}

}  // namespace corebox
