// `corebox bench pile`: the ball-pile scene (bench_scenes.h, the scene of assets/pile.toml) at several
// N, timed per 1/60 s frame of `substeps` steps, and judged as a game would judge it: does the pile
// come to rest, with no ball escaping, overlaps under 1% of a diameter and no energy gained? The same
// scene runs in Bullet (corebox_bullet_pile, built where libbullet-dev is installed) in the same run
// for the CPU backend, so both engines are timed on one machine. Writes PREFIX.csv (one row per run)
// and PREFIX.json (with the hardware, the command, the scene and the targets).
//
// Design note. A run that blows up is a result, not an error: InstabilityError (what `corebox run`
// turns into exit code 3) and DeviceError are caught and recorded with their message, the frames up
// to the failure keep their timings, the final measures come from the last good state, and the
// benchmark goes on with the next run. Only bad options (an unknown backend, a missing --bullet
// driver, an unwritable --out) stop it. Frame time is the wall time of the steps of a frame, the
// backend finished; the per-frame energy sample (Simulation::observe, the check `corebox run` makes
// at every observation) is taken outside it.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "scene.h"

namespace corebox {

struct PileBenchmarkOptions {
    std::string backend = "cpu";  // cpu | cuda | auto
    int threads = 0;              // CPU threads; 0: all cores
    // Ball counts; empty: 2000, 10000, 40000 on the CPU and 10^4, 10^5, 10^6 on CUDA.
    std::vector<int64_t> sizes;
    std::vector<Precision> precisions{Precision::Fp32, Precision::Fp64};
    // Simulated time per run [tau]. The top of the 60-high box lands ~3.2 s in and the pile is at rest
    // by ~4 s (Bullet: 3.3 s at 10,000 balls, 3.9 s at 2,000), so 3 s cannot show rest.
    double seconds = 5.0;
    int substeps = 4;          // steps per 1/60 s frame: dt = 1 / (60 substeps)
    int contactSweeps = 0;     // [interaction] contact_sweeps of the scene (0: the backend's own cap)
    int roundCap = 0;          // [interaction] max_collision_rounds of the scene (0: the scene's own, 64)
    std::string bulletPath;    // the Bullet driver; "": corebox_bullet_pile beside this program if built; "none": skip
    std::string outputPrefix;  // writes PREFIX.csv and PREFIX.json; "": CSV on stdout only
    // Writes TRACE_<backend>_<precision>_<n>.csv for each corebox run: a row per frame with the
    // collision stage's work and host-clock time by phase, to see where a forming and a resting pile
    // spend their frames. "": no trace.
    std::string tracePrefix;
    std::string commandLine;
};

struct PileRunResult {
    std::string engine;   // corebox | bullet
    std::string backend;  // cpu | cuda (corebox); bullet
    std::string device;
    std::string precision;  // fp32 | fp64
    int threads = 0;
    int64_t n = 0;
    std::array<double, 3> box{};
    bool boxGrown = false;  // the box was widened to fit n (bench_scenes.h: pileBox)
    int substeps = 0;
    double dt = 0;
    double secondsRequested = 0;
    double secondsSimulated = 0;
    int64_t frames = 0;  // frames completed
    double msPerFrameMean = 0;
    double msPerFrameLastSecond = 0;
    double maxOverlap = 0;          // fraction of the diameter, final state
    double maxWallPenetration = 0;  // fraction of the diameter, final state
    int64_t outside = 0;            // balls outside the box (or not finite), final state
    double energyStart = 0;         // E_kin + E_pot (+ E_dissipated for corebox)
    double energyEnd = 0;
    double energyChangeRelative = 0;  // (end - start) / start; > 0 is energy gained
    double potentialReleased = 0;
    double dissipated = 0;  // corebox's count of collision losses; Bullet does not report one
    double kineticEnd = 0;
    std::optional<double> timeToRest;  // none: not at rest at the end, or the run failed
    int64_t roundCapHits = -1;         // steps whose collision rounds hit the cap (-1: not applicable)
    int maxRounds = -1;                // most collision rounds in one step (-1: not applicable)
    double meanRounds = -1;            // impact rounds per step, mean (-1: not applicable)
    double meanContactSweeps = -1;     // contact sweeps per step, mean (-1: not applicable)
    double meanListings = -1;          // contact lists made per step, mean (-1: not applicable)
    int contactSweepCap = -1;          // the scene's contact_sweeps (0: the backend's own; -1: not applicable)
    int roundCap = -1;                 // the scene's max_collision_rounds (-1: not applicable)
    // Listings whose sweeps hit the cap with the approach speed / the overlap above tolerance, per step
    double cappedSpeedPerStep = -1, cappedOverlapPerStep = -1;
    double jacobiListingsPerStep = -1;  // listings relaxed with Jacobi sweeps, per step
    double msPerFrameMax = 0;           // the slowest frame
    double collideShare = -1;          // share of the step's marked phases spent in the collision stage
    double impactShare = -1;           // of the collision stage's time: the screen and the impact rounds ...
    double contactShare = -1;          // ... and the contact phase (listings and sweeps)
    double listingShare = -1;          // of the contact phase's time: the listings (and colourings)
    std::string finalState;            // "end" or "last_good" (the state before the failing step)
    std::string outcome;               // ok | instability | device_error | error
    std::string message;
    std::vector<double> frameMs;  // each frame's wall time: compares a failed run with Bullet over its frames
};

std::vector<PileRunResult> runPileBenchmark(const PileBenchmarkOptions& options);

}  // namespace corebox
