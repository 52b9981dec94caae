// What the collision stage gave to the walls and through the pairs, for the pressure observables
// (src/core/pressure.h), summed by both phases of the stage (collision_resolution.h for impacts,
// contact_relaxation.h for resting contacts) on every backend.
//
// Why impulses and not forces: hard cores act only through impulses, so the pressure is measured the
// way an experiment measures it, as momentum given to the walls per area and time, and the pair
// part of the virial as sum r_ij . J_ij over the impulses of a window, divided by its length.
// Resting contacts count too: a pile's floor bears its weight through the contact phase's impulses.
//
// The centre of a wall: the part of its face whose two tangential coordinates lie in the middle half
// of the region open to centres ([a, L - a] on each axis), a quarter of the face. Next to a wall the
// fluid's tangential stress differs from its pressure (the wall's surface tension), and where two
// walls meet that stress pushes on both: momentum given near the edges carries an O(1 / L) surface
// term. Away from the edges the normal stress is the bulk pressure (momentum balance along the normal
// through the bulk), so wallCentre measures the bulk pressure even in a box of a few tens of
// diameters (docs/hard_spheres.md).
//
// Signs: wall[2 axis + side] is the momentum a wall received along its outward normal (>= 0 for a
// wall that only pushes); pairVirial sums r_ij . J_ij with r_ij = x_i - x_j and J_ij the impulse on
// i from j (> 0 for a repulsive impulse), each pair impulse once.
#pragma once

#include "hd.h"
#include "vec3.h"

namespace corebox {

constexpr int kWallCount = 6;  // index 2 axis + side (side 0: the wall at 0, side 1: the wall at L)

struct ImpulseSums {
    double wall[kWallCount] = {0, 0, 0, 0, 0, 0};        // [m sigma / tau]
    double wallCentre[kWallCount] = {0, 0, 0, 0, 0, 0};  // the part of wall[] given at its centre
    double pairVirial = 0;                               // [m sigma^2 / tau]

    COREBOX_HD ImpulseSums& operator+=(const ImpulseSums& o) {
        for (int k = 0; k < kWallCount; ++k) {
            wall[k] += o.wall[k];
            wallCentre[k] += o.wallCentre[k];
        }
        pairVirial += o.pairVirial;
        return *this;
    }
    COREBOX_HD void addWall(int code, double impulse, bool atCentre) {
        wall[code] += impulse;
        if (atCentre) wallCentre[code] += impulse;
    }
    COREBOX_HD double wallTotal() const {
        double sum = 0;
        for (int k = 0; k < kWallCount; ++k) sum += wall[k];
        return sum;
    }
};

// Whether a particle at x touching a wall of `axis` does so at the wall's centre (above).
template <class Real>
COREBOX_HD inline bool atWallCentre(Vec3<Real> x, Real radius, Vec3<Real> box, int axis) {
    for (int k = 0; k < 3; ++k) {
        if (k == axis) continue;
        const Real quarter = Real(0.25) * (box[k] - Real(2) * radius);
        if (!(x[k] >= radius + quarter && x[k] <= box[k] - radius - quarter)) return false;
    }
    return true;
}

// Rows of the per-particle form (GPU: one row of n doubles each, summed in a fixed order):
// the six walls, their centres, then the pair virial.
constexpr int kImpulseRows = 2 * kWallCount + 1;
constexpr int kPairVirialRow = 2 * kWallCount;

}  // namespace corebox
