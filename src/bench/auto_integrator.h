// method = "auto": the cheapest method, precision and step that keep the conserved sum within the
// scene's tolerance (relative energy error per unit time), chosen at start by a pilot study.
//
// Design note. Candidates are Verlet, its compositions (Forest-Ruth, PEFRL, Blanes-Moan, Yoshida 6
// and 8) and RK4, each at the scene's dt times 8, 4, 2, 1, 1/2, ... 1/16, in the scene's precision
// and, on a GPU, in the other one too (Euler and RK2 gain energy at every step and are never
// candidates). Each runs from the scene's initial state for a pilot time L (by default 500 of the
// scene's steps), observing the conserved sum 10 times; it meets the tolerance when
// max |E - E0| / (energy scale) over L, divided by L, is at most half the tolerance (the margin is
// for the run that follows: a longer run meets larger excursions, a close encounter or a pair
// crossing the cutoff; for a symplectic method, whose error oscillates, the measure is conservative). The cost is measured wall time per
// unit time on this machine and backend, not force passes alone: a large step lets cores overlap
// deeply and adds collision rounds and neighbour-list rebuilds that force passes do not count, and a
// GPU's fp32 and fp64 differ in speed at equal passes. Force passes order the search: candidates run
// from the fewest passes per unit time up, and the search stops once a candidate's passes, at the
// fastest rate per pass measured so far, would cost more than the best run that met the tolerance;
// a run that passes that cost is stopped ("too_slow"). Runs within 15% of the fastest are a tie,
// won by the one with fewer force passes, so timing noise rarely changes the choice. A budget of wall time bounds the pilot; when it runs out, or no
// candidate meets the tolerance, the most accurate run tried is chosen and the line printed says
// that the tolerance was not met.
// With --study FILE the app first looks for the answer in a study of the scene (study_curves.h:
// chooseIntegratorFromStudy, by force passes since the study may come from another machine) and runs
// the pilot only when no run of the study meets the tolerance.
// A scene with no pair force integrates constant accelerations (gravity or none), which Verlet
// does exactly between collisions: it gets Verlet at its dt without a pilot.
#pragma once

#include <string>
#include <vector>

#include "backend_factory.h"
#include "particle_state.h"
#include "scene.h"

namespace corebox {

struct AutoIntegratorOptions {
    std::string backend = "auto";
    int threads = 0;
    double pilotTime = 0;        // L [tau]; 0: 500 of the scene's steps
    double budgetSeconds = 20;   // wall time after which the pilot settles for the best run so far
};

struct PilotTrial {
    Method method = Method::Verlet;
    Precision precision = Precision::Fp64;
    double dt = 0;
    double errorPerTime = 0;        // max |E - E0| / scale over L, divided by L [1/tau]
    double forcePassesPerTime = 0;  // measured
    double wallSecondsPerTime = 0;  // measured on this machine and backend
    std::string outcome = "ok";     // the blow-up's kind (instabilityKind), or "too_slow": stopped once
                                    // it cost more than the best run that met the tolerance
    bool meets = false;
};

struct AutoIntegratorChoice {
    IntegratorDef integrator;        // the choice (automatic = false)
    double tolerance = 0;
    bool met = false;                // a pilot run met the tolerance
    bool piloted = false;            // false: no pair force, no pilot needed
    PilotTrial chosen;
    std::vector<PilotTrial> trials;  // in the order run
    double pilotSeconds = 0;
    std::string summary;             // what was chosen and why, one line
};

// Throws InputError when every pilot run blew up, DeviceError from the backend.
AutoIntegratorChoice chooseIntegrator(const Scene& scene, const ParticleState& initial, const AutoIntegratorOptions& options);

// `scene` with its automatic integrator resolved (unchanged when not automatic); `summary` gets the
// choice's line ("" when not automatic), which is also printed unless `quiet`.
Scene resolveAutomaticIntegrator(const Scene& scene, const BackendChoice& backend, bool quiet, std::string* summary = nullptr);

}  // namespace corebox
