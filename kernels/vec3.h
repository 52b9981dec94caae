// Minimal 3-vector used by the physics headers on host and device. Deliberately a plain aggregate
// (no constructors beyond aggregate init) so arrays of it are trivially copyable to and from
// device memory and CSV buffers.
#pragma once

#include <cmath>

#include "hd.h"

namespace corebox {

template <class Real>
struct Vec3 {
    Real x, y, z;

    COREBOX_HD Real& operator[](int axis) { return axis == 0 ? x : (axis == 1 ? y : z); }
    COREBOX_HD Real operator[](int axis) const { return axis == 0 ? x : (axis == 1 ? y : z); }
};

template <class Real>
COREBOX_HD inline Vec3<Real> operator+(Vec3<Real> a, Vec3<Real> b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
template <class Real>
COREBOX_HD inline Vec3<Real> operator-(Vec3<Real> a, Vec3<Real> b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
template <class Real>
COREBOX_HD inline Vec3<Real> operator*(Real s, Vec3<Real> a) { return {s * a.x, s * a.y, s * a.z}; }
template <class Real>
COREBOX_HD inline Vec3<Real>& operator+=(Vec3<Real>& a, Vec3<Real> b) { a.x += b.x; a.y += b.y; a.z += b.z; return a; }
template <class Real>
COREBOX_HD inline Vec3<Real>& operator-=(Vec3<Real>& a, Vec3<Real> b) { a.x -= b.x; a.y -= b.y; a.z -= b.z; return a; }
template <class Real>
COREBOX_HD inline Real dot(Vec3<Real> a, Vec3<Real> b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
template <class Real>
COREBOX_HD inline Real norm2(Vec3<Real> a) { return dot(a, a); }

template <class To, class From>
COREBOX_HD inline Vec3<To> vec3Cast(Vec3<From> a) { return {To(a.x), To(a.y), To(a.z)}; }

}  // namespace corebox
