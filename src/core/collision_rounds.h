// The a posteriori collision stage of a step (DESIGN.md sec. 2; the report's sec. 4), written once
// for every backend, in two phases.
//
// 1. Impacts. The report resolves the earliest event first until none remain; here that runs in
//    parallel rounds: in each round every particle finds its earliest event (a pair overlap or a
//    wall penetration that began within this step and approaches faster than the resting speed,
//    rewound to its contact time), and every event that is the earliest of each particle it touches
//    is resolved with restitution e. Those events form a matching, so a backend resolves them
//    concurrently. A round looks again only where something happened: active particles (with an
//    event in the previous round) against every neighbour, the others against active neighbours.
//    The number of rounds is capped; when the cap is hit, a last search says whether impacts remain
//    (reported), and the contact phase takes what is left.
// 2. Contacts. Every overlapping or touching pair and wall is relaxed together by sweeps
//    (contact_relaxation.h: over-relaxed Gauss-Seidel on the CPU, accelerated Jacobi on the GPU):
//    approach velocities stopped (restitution 0: resting contact), overlaps removed by moving
//    positions without adding kinetic energy, until the largest approach speed and overlap are within
//    tolerance or the sweep cap is reached (RelaxationPlan: the host checks after each batch, the GPU
//    checks within its one launch on the same schedule). The kinetic energy this removes,
//    minus the work done against gravity by the position moves, is booked as dissipated, so
//    E_kin + E_pot + E_dissipated stays exact.
// Both phases report their impulses (impulse_sums.h: what the walls received, r_ij . J_ij of the
// pairs) into the step report, for the pressure observables (pressure.h).
// Why two phases and Jacobi: see the design note of kernels/contact_relaxation.h.
#pragma once

#include "backend.h"
#include "step_report.h"

namespace corebox {

struct CollisionSettings {
    // Impact rounds per step. A lower cap is not a cheaper landing: what the rounds leave, the contact
    // phase takes, with more listings and sweeps. `corebox bench pile --max-rounds 64|32|16` (an H200,
    // fp32, one call): 10^6 balls 97.5 / 89.8 / 88.5 ms a frame; its frames from 1 to 2 s (the landing)
    // 186 / 157 / 157 ms, the impacts 77.5 / 50.8 / 30.7 ms of them and the contacts 108.5 / 106.1 /
    // 126.1; the settled pile the same (53.5 ms); 240 / 413 / 531 steps at the cap; 10^5 balls 26.8 /
    // 23.4 / 22.4 ms. Rest, overlaps and the energy balance did not change. A tenth off the mean is not
    // worth impacts losing their restitution in four steps of ten of the landing: the cap stays.
    int maxRounds = 64;
    double dt = 0;                 // the step just taken: no rewind beyond it
    double restingSpeed = 0;       // slower contacts rest instead of bouncing [sigma / tau]
    // Contact sweeps per listing. A warm-started Gauss-Seidel relaxation begins near its end and
    // carries support from the floor to the top within a sweep, so it needs few (the 10,000-ball pile,
    // CPU: 16 sweeps 116 ms per frame with overlaps within 0.04% of a diameter; 32 sweeps 157 ms,
    // 0.05%; capped at 128, 420 ms). Jacobi carries support a layer per sweep and needs many (H200,
    // plain and warm-started with 16: a column of ten balls sank 1.6e-3 and a pile's overlaps reached
    // 1e-3); accelerated, fewer (contact_relaxation.h: 233 a step in a forming 10^5-ball pile).
    // Plain Gauss-Seidel hands a deep pile's momentum to the floor about a layer per sweep: 4444 balls on
    // a 10 x 10 floor (a 40-layer pile, as deep as the 40,000-ball one, CPU fp64) never settled at 16
    // sweeps (from 3 s on the pile moved down faster with height, 6 sigma/tau at the top, the kinetic
    // energy steady at 5% of the potential energy released), and more sweeps only masked it (128: at
    // rest by 4 s, the 10,000-ball pile 3.5x slower). Over-relaxed (contact_relaxation.h:
    // kGaussSeidelOverRelaxation) 16 suffice: that pile at 6.5e-5 by 6 s, the 40,000-ball pile at rest
    // by 2.25 s. The GPU's coloured Gauss-Seidel sweeps take the same cap (contact_gauss_seidel.cu:
    // on that 40-layer pile 16 of them did what 128 Jacobi sweeps did). Fewer do not pay on the GPU
    // either: `corebox bench pile --contact-sweeps 8|12|16` (an H200, fp32, one call) took 10^6 balls 72.0
    // / 55.2 / 53.0 ms a frame over the last second, the pile's kinetic energy at 5 s 2.5e5 / 3.3e4 /
    // 1.7e4 and its overlaps 0.39% / 0.16% / 0.08% of a diameter (10^5 balls: 17.0 / 12.9 / 12.2 ms,
    // 3.1e4 / 5.4e3 / 1.7e3): a pile relaxed less rattles, lists again and takes more impact rounds.
    // Measured again once the impact rounds skipped and count-sorted their cell lists and a listing was
    // made again only from overlaps of 2% of a diameter (collision_rounds.cpp): an H200, fp32, one call,
    // 8 / 12 / 16, 10^6 balls 39.6 / 42.7 / 47.2 ms a frame (the last second 30.7 / 34.9 / 39.7), the
    // kinetic energy at 5 s 2.4e4 / 9.1e3 / 7.9e3, overlaps 0.15% / 0.05% / 0.05%, rest at 2.23 / 2.20 /
    // 2.20 s. 12 was kept for a call, and then the settled 400-ball pile of the dense-contact tests fell
    // onto its lower layers on the GPU at 0.0126 a ball a step, where they allow 0.0102 (a quarter of
    // g dt; the CPU's bottom-up sweeps held it): 16 stays.
    // A settled pile never meets the tolerances (RelaxationPlan), so the cap, not the residual, sets
    // its cost: on the CPU (10,000 balls, fp64, the settled pile at 4 s) the largest speed change of a
    // sweep falls from about 1.3 to 0.11 over 16 sweeps, with most contacts still changing by more
    // than the tolerance (0.1 g dt); with 64 sweeps a listing every listing still reached the cap and
    // the kinetic energy at 5 s was 738 against 794, for 2.7 times the time a frame.
    // [interaction] contact_sweeps replaces both caps.
    int maxSweepsJacobi = 128;
    int maxSweepsGaussSeidel = 16;
    // Contact listings per step: a listing whose overlaps started deeper than 2% of a diameter is listed
    // again (collision_rounds.cpp), up to this many; what the last leaves, the next step takes on.
    // [interaction] contact_listings lowers it, as a game fixes its solver budget. The sandbox example
    // at 10^5 balls (an H200, fp32, scripted, 16 impact rounds and 8 sweeps, three runs each in one call)
    // with caps 32 / 3 / 2 / 1: 5.95 to 6.00 / 5.91 to 5.97 / 5.79 to 5.82 / 5.56 to 5.65 ms a frame, the
    // landing (frames 158 to 183) 13.7 to 13.9 / 13.2 to 13.5 / 11.7 to 11.8 / 8.8 to 9.0, the slowest
    // frame 16.1 to 16.5 / 15.6 to 16.1 / 13.8 to 14.4 / 11.5 to 11.7; 1483 / 1457 / 1383 / 1258 listings
    // in 1680 steps; the deepest overlap a step left 0.56% / 0.51% / 0.81% / 6.5% of a diameter; at the
    // end the same rest (kinetic energy 0.0024 to 0.0038 a ball, overlaps within 1.7e-4). 10^4 balls,
    // 32 / 2 / 1: the landing 4.8 to 5.0 / 4.6 / 4.2 ms, the slowest 14.5 / 11.8 / 9.3, overlaps left
    // 0.54% / 1.0% / 4.9%. One listing leaves overlaps a player sees; corebox's own stays at 32.
    int maxListings = InteractionDef::kMaxContactListings;
    double speedTolerance = 0;     // contacts converged when no approach is faster than this ...
    double overlapTolerance = 1e-3;  // ... and no overlap deeper than this fraction of a contact distance
};

// Settings for a step of length dt under gravity g: the resting speed is 12 |g| dt, what gravity adds
// to an approach in twelve steps (0 without gravity: every approach is then an impact); the reasons are
// with kRestingSteps in collision_rounds.cpp.
// `smallestContact`: the smallest contact distance a_i + a_j of the scene (the overlap tolerance is
// relative to it).
CollisionSettings collisionSettingsFor(const InteractionDef& interaction, double dt, double smallestContact);

// Runs both phases on the backend's current state; fills the collision fields of `report`.
void resolveCollisions(Backend& backend, const CollisionSettings& settings, StepReport& report);

}  // namespace corebox
