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

}  // namespace corebox
