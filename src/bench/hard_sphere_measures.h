// Measures of the elastic hard-sphere fluid in a box with hard walls (header-only, core types only),
// shared by `corebox bench hardspheres` and the physics tests that judge it against Carnahan-Starling
// and Enskog (hard_sphere_theory.h).
//
// Design note: why a bulk region. Next to a hard wall the fluid layers: the density at contact is
// P / kT (Z times the bulk density) and oscillates for a few diameters. Pressure is uniform (the
// walls' momentum is the bulk's pressure), but the number density that goes into Z = P / (n kT) must
// be the bulk's, not N / V. So density and collision frequency are measured in a central cube whose
// faces are `margin` diameters inside the faces of the region open to centres (pressure.h), where the
// layering has died out (checked: the density there does not change when the margin grows).
//
// The collision frequency per particle in that region comes from velocities: without forces and
// gravity a velocity changes only in a collision, and a centre more than a radius from every wall
// meets no wall. Of the m particles in the region at the start of a step, c changed velocity by its
// end; with Poisson statistics over a short step, Gamma = -ln(1 - c/m) / dt (the log counts the
// particles that collided twice in the step; at 0.02 collisions per particle per step the correction
// is 1%). This is the per-particle frequency Enskog's Gamma describes, free of the walls; the box's
// total pair collision count is reported beside it.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <memory>

#include "initial_conditions.h"
#include "particle_state.h"
#include "simulation.h"

namespace corebox {

struct BulkRegion {
    std::array<double, 3> low{}, high{};
    double volume = 0;
    bool contains(const Vec3<double>& x) const {
        for (int k = 0; k < 3; ++k) {
            if (!(x[k] >= low[size_t(k)] && x[k] < high[size_t(k)])) return false;
        }
        return true;
    }
};

// Centres at least `margin` inside each face of [radius, L - radius]^3.
inline BulkRegion bulkRegionOf(const std::array<double, 3>& box, double radius, double margin) {
    BulkRegion r;
    r.volume = 1;
    for (int k = 0; k < 3; ++k) {
        r.low[size_t(k)] = radius + margin;
        r.high[size_t(k)] = box[size_t(k)] - radius - margin;
        r.volume *= std::max(r.high[size_t(k)] - r.low[size_t(k)], 0.0);
    }
    return r;
}

inline int64_t countInside(const ParticleState& state, const BulkRegion& region) {
    int64_t count = 0;
    for (const Vec3<double>& x : state.position) count += region.contains(x) ? 1 : 0;
    return count;
}

// Accumulates the bulk density, collision frequency and virial pressure over samples (spheres of
// diameter `sigma` and mass `mass`).
//
// The bulk's own virial pressure from the same velocity changes: in a collision at contact r_ij =
// sigma n and the impulse on each particle is m |dv| along n, so r_ij . J_ij = sigma m |dv_i| = sigma
// m |dv_j|: half of it per particle. Over the particles in the region (each collision with a partner
// outside counts half, the usual particle-based local virial, exact on average in a homogeneous
// region): P_bulk = <sum_i m v_i^2> / (3 V_r) + sigma sum m |dv_i| / (6 V_r t).
struct BulkSampler {
    BulkRegion region;
    double sigma = 1, mass = 1;
    int64_t densitySamples = 0, counted = 0;  // sum over density samples of the particles inside
    int64_t stepSamples = 0;
    int64_t inside = 0, changed = 0;  // over step samples: particles in the region, those that collided
    double sampledTime = 0;           // sum of dt over step samples
    double sampledTimeWeighted = 0;   // sum of dt times the particles inside
    double kinetic2 = 0;              // sum over step samples of sum_i m v_i^2 in the region
    double impulse = 0;               // sum over step samples of sum_i m |dv_i| in the region

    void sampleDensity(const ParticleState& state) {
        ++densitySamples;
        counted += countInside(state, region);
    }
    // `before` and `after` one step of length dt.
    void sampleStep(const ParticleState& before, const ParticleState& after, double dt) {
        int64_t in = 0;
        for (size_t i = 0; i < before.size(); ++i) {
            if (!region.contains(before.position[i])) continue;
            ++in;
            const Vec3<double> d = after.velocity[i] - before.velocity[i];
            const double dv2 = norm2(d);
            changed += dv2 > 0 ? 1 : 0;
            impulse += mass * std::sqrt(dv2);
            kinetic2 += mass * norm2(before.velocity[i]);
        }
        ++stepSamples;
        inside += in;
        sampledTime += dt;
        sampledTimeWeighted += dt * double(in);
    }
    double density() const { return densitySamples > 0 ? double(counted) / (double(densitySamples) * region.volume) : 0.0; }
    // kT of the particles in the region, from the step samples.
    double temperature() const { return inside > 0 ? kinetic2 / (3.0 * double(inside)) : 0.0; }
    // Collisions per particle per unit time.
    double collisionFrequency() const {
        if (inside == 0 || !(sampledTimeWeighted > 0)) return 0;
        const double fraction = double(changed) / double(inside);
        const double meanDt = sampledTimeWeighted / double(inside);
        return -std::log1p(-fraction) / meanDt;
    }
    double virialPressure() const {
        if (stepSamples == 0 || !(region.volume > 0) || !(sampledTime > 0)) return 0;
        return kinetic2 / (3.0 * region.volume * double(stepSamples)) + sigma * impulse / (6.0 * region.volume * sampledTime);
    }
};

// Runs the scene for `time` tau in `stretches` stretches from `state`, redrawing every velocity
// (Maxwell-Boltzmann at the scene's temperature, seed + stretch) before each; returns the simulation
// that ran the last stretch, ready to measure. make(scene, state) builds a Simulation.
template <class Make>
std::unique_ptr<Simulation> equilibrateIsothermally(const Scene& scene, ParticleState state, double time, int stretches, Make&& make) {
    std::unique_ptr<Simulation> sim;
    const int64_t steps = std::llround(time / scene.integrator.dt / std::max(stretches, 1));
    for (int k = 0; k < std::max(stretches, 1); ++k) {
        Scene draw = scene;
        draw.init.seed = scene.init.seed + uint64_t(k) + 1;
        assignMaxwellBoltzmannVelocities(draw, state);
        sim = make(scene, state);
        for (int64_t s = 0; s < steps; ++s) sim->step();
        state = sim->state();
    }
    return sim;
}

}  // namespace corebox
