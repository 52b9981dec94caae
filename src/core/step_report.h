// What one step did: the step size taken, collision counts and losses, resolution rounds, and where
// the time went. Made by the core's step orchestration (simulation.cpp) for the front ends.
#pragma once

#include <cstdint>

namespace corebox {

struct StepReport {
    double dt = 0;                 // the step actually taken (adaptive dp5 may shrink it)
    int rejectedSteps = 0;         // adaptive attempts rejected before this one
    int64_t pairCollisions = 0;    // particle-particle impulses applied
    int64_t wallCollisions = 0;    // wall reflections applied
    int64_t positionalFixes = 0;   // overlaps separated without an impulse (not approaching)
    double dissipated = 0;         // kinetic energy lost in inelastic collisions this step [eps]
    int rounds = 0;                // parallel resolution rounds used
    bool roundCapHit = false;      // overlaps remained after InteractionDef::maxCollisionRounds
    // Where the step's time went [s]: force passes, the rest of the integration, collisions.
    double secondsForces = 0, secondsIntegrate = 0, secondsCollide = 0;
};

}  // namespace corebox
