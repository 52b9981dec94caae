// What one step did: the step size taken, collision counts and losses, resolution rounds, and where
// the time went. Made by the core's step orchestration (simulation.cpp) for the front ends.
#pragma once

#include <cstdint>

#include "collision_screen.h"  // StageScreen
#include "impulse_sums.h"

namespace corebox {

struct StepReport {
    double dt = 0;                 // the step actually taken (adaptive dp5 may shrink it)
    int rejectedSteps = 0;         // adaptive attempts rejected before this one
    int64_t pairCollisions = 0;    // particle-particle impulses applied
    int64_t wallCollisions = 0;    // wall reflections applied
    int64_t contacts = 0;          // contacts relaxed after the impacts (pairs counted from both sides, walls once)
    double dissipated = 0;         // kinetic energy lost in collisions and contacts this step [eps]
    int rounds = 0;                // parallel impact rounds used
    StageScreen screen = StageScreen::Full;  // what the backend's screen found (the stage ran whole, for walls, or not)
    bool roundCapHit = false;      // impacts remained after InteractionDef::maxCollisionRounds
    int contactSweeps = 0;         // sweeps of the contact relaxation (all listings)
    int contactListings = 0;       // contact lists made (a deep overlap lists again)
    // Listings whose sweeps reached the cap (CollisionSettings) with the approach speed, or the
    // overlap, still above its tolerance: which of the two levels the cap cut short.
    int contactCappedSpeed = 0, contactCappedOverlap = 0;
    int contactListingsJacobi = 0;  // listings the backend relaxed with Jacobi sweeps (relaxesGaussSeidel false)
    double contactOverlap = 0;     // largest overlap left, as a fraction of the contact distance
    ImpulseSums impulses;          // impacts and contacts: given to the walls, r_ij . J_ij of the pairs
    // Where the step's time went [s]: force passes, the rest of the integration, collisions (on a GPU
    // the device's own clock, possibly one step late: Backend::phaseSeconds).
    double secondsForces = 0, secondsIntegrate = 0, secondsCollide = 0;
    // secondsCollide split: the impact rounds (with the screen) and the contact phase [s], and of the
    // contact phase the listings (contact lists, and the colouring where the sweeps are coloured) [s].
    double secondsImpacts = 0, secondsContacts = 0, secondsListings = 0;
};

}  // namespace corebox
