// `corebox study SCENE`: speed against accuracy for every method on one scene (issue: the study).
//
// Design note. Every run starts from the scene's own initial state, on one backend, and differs from
// the others only in method, precision and step, so the differences measure the methods:
// - accuracy (a): the positions at a short horizon T against a reference trajectory, RMS over the
//   particles in sigma. The reference is Hairer 10 in fp64 at a quarter of the smallest step of the
//   ladder, checked by the same method at half that step: the difference of the two is reported as
//   the reference's own error, the floor below which no error of the study means anything. T is
//   short (by default 100 of the scene's steps) so that chaos has not yet separated trajectories,
//   which would make every error the size of the box whatever the method;
// - accuracy (b): the conserved sum (kinetic + potential + dissipated + thermostat work) over a long
//   run L, relative to the simulation's energy scale (the blow-up detector's): its largest excursion
//   and its drift rate (least-squares slope per unit time);
// - cost: force passes per unit simulated time (machine-independent: what a method costs on any
//   hardware) and wall seconds per unit simulated time on this machine and backend;
// - stability: the largest stable step of each method, found by doubling then bisecting, where a
//   trial of length L fails when the blow-up detector stops it (non-finite values, an escape, energy
//   growth beyond its limit, runaway kinetic energy, an adaptive step that cannot meet its tolerance),
//   its energy limit tightened from half the energy scale to 1% of it (--drift-limit): a weakly
//   unstable step in a nonlinear scene grows until its frequency softens and may then saturate below
//   the loose limit (RK4 on the LJ pair "survived" 200 periods at omega dt 2.97 > 2.83 with it)
//   or when the collision rounds hit their cap on more than 1% of its steps; the failure's kind is
//   recorded.
// The scene's thermostat is switched off: the study measures the integration, and a thermostat's
// kicks (Bussi's are random, drawn once per step) make runs at different steps different processes,
// whose trajectories do not converge to one another.
// Fixed-step runs land on T exactly (the step is T / round(T / dt)); adaptive DP5 runs at each
// tolerance have their last step shortened to land on T.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "blow_up_recovery.h"
#include "butcher_tableau.h"
#include "particle_state.h"
#include "scene.h"

namespace corebox {

struct StudyOptions {
    std::string scenePath;
    std::string backend = "auto";
    int threads = 0;
    std::vector<Method> methods;                              // empty: every method
    std::vector<Precision> precisions{Precision::Fp64, Precision::Fp32};
    std::vector<double> dtFactors{4, 2, 1, 0.5, 0.25, 0.125};  // the ladder, as multiples of the scene's dt
    std::vector<double> tolerances{1e-4, 1e-6, 1e-8, 1e-10};   // adaptive dp5 runs
    double horizon = 0;                                       // T [tau]; 0: 100 of the scene's steps
    double longRun = 0;                                       // L [tau]; 0: 10 T
    bool stability = true;
    double driftLimit = 0.01;  // a stability trial fails when the conserved sum moves by more than this
                               // fraction of the energy scale (the blow-up detector's bound, made strict)
    bool quiet = false;
    std::string outputPrefix;  // PREFIX.csv and PREFIX.json; empty: CSV on stdout only
    std::string commandLine;
};

// One run of the ladder.
struct StudyRun {
    Method method = Method::Rk4;
    Precision precision = Precision::Fp64;
    double dt = 0;         // the step (adaptive: the mean step over the long run)
    double tolerance = 0;  // adaptive dp5 only; 0 otherwise
    double stateError = 0;            // RMS position error at T [sigma]
    double energyErrorMax = 0;        // max |E - E0| / scale over L
    double energyDriftRate = 0;       // slope of (E - E0) / scale [1 / tau]
    double forcePassesPerTime = 0;    // force passes per unit simulated time (short run)
    double wallSecondsPerTime = 0;    // wall seconds per unit simulated time (long run)
    std::string outcome = "ok";       // ok, or the failure's kind (instabilityKind)
    std::string message;
};

// The largest stable step of a method in a precision.
struct StabilityLimit {
    Method method = Method::Rk4;
    Precision precision = Precision::Fp64;
    double stableDt = 0;    // largest step seen to survive L (0: none did)
    double unstableDt = 0;  // smallest step seen to fail (0: none failed up to the largest tried)
    std::string failure;    // how the smallest failing step failed
};

struct StudyResult {
    std::string device;
    int64_t particles = 0;
    double horizon = 0, longRun = 0;
    std::string thermostat;       // "none", or what was switched off
    std::string reference;        // "hairer10 fp64 dt = ..."
    double referenceError = 0;    // RMS difference of the reference and its check at half the step [sigma]
    std::vector<Method> methods;
    std::vector<Precision> precisions;
    std::vector<StudyRun> runs;
    std::vector<StabilityLimit> limits;
};

// Runs the study of `scene` from `initial`; `progress(done, total, what)` is called before each run.
StudyResult runStudy(const Scene& scene, const ParticleState& initial, const StudyOptions& options,
                     const std::function<void(int, int, const std::string&)>& progress = nullptr);

// The order of convergence a method shows in the study's own output: the least-squares slope of
// log(state error) against log(dt) over its fixed-step runs whose error lies between 10 times the
// reference's own error (and 1e-12 sigma) and 1e-2 sigma, where the error is neither round-off nor
// saturated; NaN when fewer than two runs qualify.
double observedOrder(const StudyResult& result, Method method, Precision precision);

// The command: loads the scene, runs the study with a progress line, writes CSV and JSON.
void runStudyCommand(const StudyOptions& options);

}  // namespace corebox
