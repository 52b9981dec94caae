// The collision stage's screen (Backend::screenStage): the reaches and bounds that decide, from one
// pass over the positions, whether a stage can be skipped or run for walls alone. Shared by the GPU's
// list pass and walls-at-once kernel (neighbour_list_kernels.cu, collision_kernels.cu) and the host
// side that reads the screen (src/cuda/cuda_collisions.cpp), so every side uses the same margins.
//
// The screen only ever decides "nothing can happen"; it must never pass over a pair or wall the
// stage would see. Hence a relative margin far above the contact slack of either precision
// (collision.h) on every reach, and bounds that round towards "near".
#pragma once

#include <cmath>

#include "hd.h"
#include "vec3.h"

namespace corebox {

constexpr double kScreenMargin = 1e-3;

// What a backend's screen of the collision stage found (Backend::screenStage): nothing near contact
// (the stage skipped), only particles at walls with every pair too far to meet in the stage (walls
// searched alone), or something else or nothing known (the whole stage).
enum class StageScreen : unsigned { Full, WallsOnly, Quiet };

// What the screen counts as near: a contact distance (a_i + a_j, or a_i for a wall) plus the contact
// phase's resting gap, widened by the margin.
template <class Real>
COREBOX_HD inline Real screenReach(Real contact, Real gap) {
    return (contact + gap) * Real(1 + kScreenMargin);
}

// How far the particle at x is inside the reach of its nearest wall: positive when it is nearer a wall
// than `reach` (or beyond it), negative when clear. A non-finite coordinate is ignored (the caller
// checks finiteness).
template <class Real>
COREBOX_HD inline Real deepestWallApproach(Vec3<Real> x, Real reach, Vec3<Real> box) {
    Real deepest = -box[0] - box[1] - box[2];  // below any approach a particle in the box can have
    for (int axis = 0; axis < 3; ++axis) {
        const Real low = reach - x[axis], high = x[axis] - (box[axis] - reach);
        if (low > deepest) deepest = low;
        if (high > deepest) deepest = high;
    }
    return deepest;
}

// A lower bound on every pair's clearance beyond its reach: the listed pairs' smallest R^2 / reach^2
// (nearestRatio; < 0 when no pair was listed) scaled by the smallest reach, and, for the pairs not
// listed (farther than the cutoff), the cutoff less the largest reach.
COREBOX_HD inline double pairClearanceBound(double nearestRatio, double smallestReach, double largestReach, double cutoff) {
    const double unlisted = cutoff - largestReach;
    if (nearestRatio < 0) return unlisted;
    const double listed = smallestReach * (sqrt(nearestRatio) - 1);
    return listed < unlisted ? listed : unlisted;
}

// Whether no pair can meet while walls are resolved: a wall impact moves its particle back by at most
// (1 + e_w) times its depth on each axis, the contact phase by its depth, so two particles close by at
// most 8 times the deepest wall depth.
COREBOX_HD inline bool wallsCannotBringPairsTogether(double clearance, double deepestWallDepth) {
    return clearance > 8 * deepestWallDepth;
}

// The screen's three words as a list pass leaves them (gpu_launch.h ForceArgs::screen: the nearest
// listed pair's R^2 / reach^2 and the deepest wall approach as float bits, a non-finite flag) read into
// a verdict, the same on the host and on the device: smallest and largest radius of the species, the
// lists' cutoff, the contact phase's resting gap.
struct ScreenScales {
    double smallestRadius, largestRadius, cutoff, contactGap;
};
COREBOX_HD inline float floatOfBits(unsigned bits) {
#if defined(__CUDA_ARCH__)
    return __uint_as_float(bits);
#else
    float f;
    __builtin_memcpy(&f, &bits, sizeof f);
    return f;
#endif
}
COREBOX_HD inline StageScreen screenVerdict(const unsigned words[3], const ScreenScales& s) {
    if (words[2] != 0) return StageScreen::Full;  // not finite: the stage and the health check say where
    const double nearest = words[0] != 0xffffffffu ? double(floatOfBits(words[0])) : -1.0;  // -1: no pair listed
    const double clearance = pairClearanceBound(nearest, screenReach(2 * s.smallestRadius, s.contactGap),
                                                screenReach(2 * s.largestRadius, s.contactGap), s.cutoff);
    if (!(clearance > 0)) return StageScreen::Full;
    const double depth = double(floatOfBits(words[1]));
    if (depth > 0) return wallsCannotBringPairsTogether(clearance, depth) ? StageScreen::WallsOnly : StageScreen::Full;
    return StageScreen::Quiet;
}

}  // namespace corebox
