// The CPU list pass's own rows with AVX2 (list_forces.h), one species: W pairs of a row at a time (4
// in fp64, 8 in fp32).
//
// Design note. The scalar pass spends most of its time in each pair's arithmetic (a division and some
// twenty multiplies and adds; the LJ fluid of `corebox bench md`, N = 32000, fp64, 2 cores: the pass
// 56% of a step, LAMMPS in the same run 8% faster than corebox). Here each lane does the scalar
// pairValue's operations in the same order (pairForceOverR, ljForceOverR: no fused multiply-add, the
// target being AVX2 alone), so every lane's force and energy are the scalar loop's bits; the W
// results are then added to the row and taken from the partners one by one in list order, as the
// scalar loop does. The pass's bits thus do not depend on whether the CPU has AVX2
// (ListPass.SimdRowsGiveTheScalarBits checks it). That needs the compiler to keep a * b + c as two
// roundings in both loops: the CPU backend builds with -ffp-contract=off (clang with -march=native
// fused them in one loop and not the other). Only the partners' positions are gathered lane by lane;
// the writes to them stay scalar, in order. Other species counts keep the scalar loop, and so does a
// CPU other than x86-64 (simdListRowsAvailable is false there).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "pair_potential.h"
#include "vec3.h"

namespace corebox {

// Whether this CPU runs the AVX2 rows (checked once).
bool simdListRowsAvailable();

// What a row's pairs add up to, carried between the AVX2 part and the scalar rest of the row.
template <class Real>
struct RowSums {
    Vec3<Real> force;
    double energy;
    Real nearest;  // the screen's smallest R^2 / reach^2 so far
};

#if defined(__x86_64__)
namespace detail {
template <class Real>
struct AvxLanes;
template <>
struct AvxLanes<double> {
    typedef double V __attribute__((vector_size(32)));
    static constexpr int kWidth = 4;
};
template <>
struct AvxLanes<float> {
    typedef float V __attribute__((vector_size(32)));
    static constexpr int kWidth = 8;
};
}  // namespace detail

// The entries [begin, end) of slot a's row (VerletList::walkChunk's ownRow: entrySlot, inThisChunk in
// `otherChunk`), W at a time as far as they go: their values added to `row` and, for partners in this
// chunk, taken from force[] (and added to energy[] with kEnergy); with kScreen, R^2 * screenInverse
// into row.nearest. Returns where the entries left for the scalar loop begin.
template <class Real, bool kEnergy, bool kScreen>
__attribute__((target("avx2"))) const uint32_t* simdListRow(const Vec3<Real>* xs, Vec3<Real>* force, double* energy, int64_t a,
                                                             const uint32_t* begin, const uint32_t* end, uint32_t otherChunk,
                                                             const PairCoefficients<Real>& p, Real screenInverse, RowSums<Real>& row) {
    using Lanes = detail::AvxLanes<Real>;
    using V = typename Lanes::V;
    constexpr int kWidth = Lanes::kWidth;
    const Vec3<Real> xa = xs[a];
    const bool cut = p.cutoff2 > Real(0);
    const Real forceScale = Real(6) * p.eps4;  // ljForceOverR's (6 eps4) inv2, left to right
    const Real minusMixing = -p.mixing;
    const uint32_t* e = begin;
    for (; end - e >= kWidth; e += kWidth) {
        int64_t b[kWidth];
        V dx = V{}, dy = V{}, dz = V{};
        for (int l = 0; l < kWidth; ++l) {
            b[l] = int64_t(e[l] & ~otherChunk);
            const Vec3<Real> xb = xs[b[l]];
            dx[l] = xa.x - xb.x;
            dy[l] = xa.y - xb.y;
            dz[l] = xa.z - xb.z;
        }
        const V r2 = dx * dx + dy * dy + dz * dz;
        if (kScreen) {
            const V ratio = r2 * screenInverse;
            for (int l = 0; l < kWidth; ++l) row.nearest = std::min(row.nearest, ratio[l]);
        }
        // ljForceOverR<Real, true> and pairForceOverR, lane by lane.
        const V inv2 = r2 > Real(0) ? Real(1) / r2 : V{};
        const V s2 = p.sigma2 * inv2;
        const V s6 = s2 * s2 * s2;
        V u = kEnergy ? p.eps4 * s6 * (s6 - p.mixing) : V{};
        V f = (forceScale * inv2) * (s6 * (Real(2) * s6 + minusMixing));
        if (cut && p.shift == int(CutoffShift::Force)) {
            V r = V{};
            for (int l = 0; l < kWidth; ++l) r[l] = std::sqrt(r2[l]);
            u += -p.energyShift + (r - p.cutoff) * p.forceAtCutoff;
            f -= p.forceAtCutoff / r;
        } else if (cut && p.shift == int(CutoffShift::Energy)) {
            u -= p.energyShift;
        }
        // keepOrZero: times 1 inside, times 0 beyond the cutoff (a NaN distance counts as inside).
        V keep = V{} + Real(p.eps4 != Real(0) ? 1 : 0);
        if (cut) keep = __builtin_convertvector(-(~(r2 >= p.cutoff2)), V) * keep;
        f = f * keep;
        if (kEnergy) u = u * keep;
        const V fx = f * dx, fy = f * dy, fz = f * dz;
        for (int l = 0; l < kWidth; ++l) {
            row.force.x += fx[l];
            row.force.y += fy[l];
            row.force.z += fz[l];
            if (kEnergy) row.energy += double(u[l]);
            if ((e[l] & otherChunk) == 0) {
                Vec3<Real>& fb = force[b[l]];
                fb.x -= fx[l];
                fb.y -= fy[l];
                fb.z -= fz[l];
                if (kEnergy) energy[b[l]] += double(u[l]);
            }
        }
    }
    return e;
}
#else
template <class Real, bool kEnergy, bool kScreen>
const uint32_t* simdListRow(const Vec3<Real>*, Vec3<Real>*, double*, int64_t, const uint32_t* begin, const uint32_t*, uint32_t,
                            const PairCoefficients<Real>&, Real, RowSums<Real>&) {
    return begin;  // never called: simdListRowsAvailable() is false
}
#endif

}  // namespace corebox
