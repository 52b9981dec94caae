// A pool break with exact hard-core contacts: 15 balls racked in a triangle, one cue impulse,
// restitution 0.95, and the bookkeeping a physics programmer checks.
//
// Why exact contacts matter: in a rack every ball touches its neighbours, so the cue ball's momentum
// must travel through a chain of simultaneous contacts. corebox resolves each contact as an impact of
// two hard spheres along their line of centres (Newton's restitution law), at the time it happens
// within the step, so momentum is conserved to rounding until a ball reaches a cushion, and every
// joule the table loses is in the dissipated energy: kinetic + dissipated equals the cue's kinetic
// energy to rounding. A penalty (spring) contact model loses both, and its break depends on the step.
#include <corebox/corebox.h>

#include <cmath>
#include <cstdio>

int main() {
    try {
        corebox::WorldDef def;
        def.boxSize = {30, 2, 60};  // the table seen from above: x across, z along, a thin y
        def.gravity = {0, 0, 0};    // rolling on the cloth is not modelled: a frictionless table
        def.restitution = 0.95;
        def.wallRestitution = 0.95;
        corebox::World world(def);

        const double d = 1.0 + 1e-9;   // a diameter and a hair: racked balls touch
        const double apexZ = 20;
        for (int row = 0; row < 5; ++row) {  // rows of 1 to 5 balls, away from the cue ball
            for (int k = 0; k <= row; ++k) {
                const corebox::Vec3d at{15 + (k - 0.5 * row) * d, 1, apexZ - row * d * std::sqrt(3.0) / 2};
                const corebox::PlacementResult p = world.addParticle({0, at, {0, 0, 0}});
                if (!p) throw corebox::InputError("racking a ball: " + p.reason);
            }
        }
        const corebox::ParticleId cue = world.addParticle({0, {15, 1, 45}, {0, 0, 0}}).id;
        const corebox::Vec3d shot{0.02, 0, -30};  // the cue's impulse [m sigma / tau], slightly off centre
        world.applyImpulse(cue, shot);
        const double k0 = 0.5 * (shot.x * shot.x + shot.z * shot.z);  // mass 1

        // Until a ball reaches a cushion only contacts act: the momentum stays the cue's impulse.
        double largestMomentumError = 0, firstCushion = -1;
        int pairImpacts = 0;
        while (world.time() < 3.0) {
            world.step();  // 1/240
            for (const corebox::Contact& c : world.contacts()) {
                if (c.kind == corebox::ContactKind::Pair) ++pairImpacts;
                if (c.kind == corebox::ContactKind::Wall && firstCushion < 0) firstCushion = world.time();
            }
            if (firstCushion < 0) {
                const corebox::Vec3d p = world.energy().momentum;
                largestMomentumError = std::fmax(largestMomentumError, std::hypot(p.x - shot.x, p.y - shot.y, p.z - shot.z));
            }
        }
        std::printf("momentum until the first cushion (t = %.4f): within %.1e of the cue's impulse |J| = %.3f\n", firstCushion,
                    largestMomentumError, std::hypot(shot.x, shot.z));
        const corebox::EnergyBalance e = world.energy();
        std::printf("after 3 s: %d ball-ball impacts\n", pairImpacts);
        std::printf("kinetic %.12f + dissipated %.12f = %.12f against the cue's %.12f (relative difference %.1e)\n", e.kinetic,
                    e.dissipated, e.kinetic + e.dissipated, k0, std::fabs(e.kinetic + e.dissipated - k0) / k0);
        std::printf("energy balance: kinetic + potential + dissipated - external = %.3e\n", e.conserved());
    } catch (const std::exception& ex) {
        std::fprintf(stderr, "pool_break: %s\n", ex.what());
        return 1;
    }
    return 0;
}
