// `corebox run SCENE ...`: load a scene, run it on a backend, write observables and the final state.
// The options as the command line gave them, their checks, and the choice between a batch, headless
// or window run (run_modes.h). Exit codes (DESIGN.md sec. 3) come from error_report.h.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>

#include "backend_factory.h"
#include "display_vocabulary.h"
#include "simulation.h"

namespace corebox {

// `--headless`: frames rendered on an EGL context and dumped as PNG (and video).
struct HeadlessOptions {
    bool enabled = false;
    int64_t frames = 0;           // frame 0 is the initial state, then one every stepsPerFrame steps
    bool framesGiven = false;     // --frames was on the command line
    int64_t stepsPerFrame = 10;
    FrameSize size{1280, 720};
    std::string outDir;
    ColorMode colorBy = ColorMode::Species;
    std::string videoPath;
    double speedMax = 0;          // colour bar top; 0: from the temperature
    bool softwareOnly = false;    // render on Mesa's software device even when a GPU is there
    bool hud = false;             // draw the histogram and plots into the frames
    bool writePng = true;         // --no-png: render and read back every frame, write no PNG (frame-rate runs)
};

struct RunOptions {
    std::string scenePath;
    int64_t steps = 1000;
    int64_t every = 100;               // observables row every K steps (and at step 0 and the end)
    std::string observablesPath;       // "" : rows go to stdout
    std::string stateOutPath;          // "" : final state not written
    BackendChoice backend;
    std::optional<Precision> precision;    // overrides [integrator] precision
    std::optional<Method> method;          // overrides [integrator] method
    std::optional<double> dt;              // overrides [integrator] dt
    std::optional<int64_t> seed;           // overrides [init] seed
    std::optional<int> gpus;               // overrides [devices] gpus (0: auto)
    std::optional<Exchange> exchange;      // overrides [devices] exchange
    std::optional<ForceModel> forces;      // overrides [interaction] forces
    double maxEnergyDrift = 0.5;
    bool quiet = false;                    // no progress lines
    bool stepsGiven = false;               // --steps was on the command line (headless runs warn: frames decide)
    HeadlessOptions headless;              // frames also bounds a window run
    std::string scriptPath;                // --script: timed commands (window and headless)
    std::string screenshotPath;            // --screenshot: the last frame as PNG
    bool noWindow = false;                 // batch run even where there is a display
    std::string checkpointPath;            // --checkpoint: written every checkpointEvery steps, at the end and on interruption
    int64_t checkpointEvery = 0;           // 0: only at the end and on interruption
    std::string restartPath;               // --restart: go on from this checkpoint (its scene, step, state)
    bool recover = false;                  // --recover: after a blow-up, back to the last good state with dt halved
    std::string integratorChoice;          // method = "auto": the pilot's choice and why (set by runCommand)
    std::string studyPath;                 // --study: the speed-vs-accuracy panel's lines
};

// Where a run that blew up writes its last good state: beside --state-out (NAME.last_good.csv),
// else beside --observables (last_good_state.csv), else corebox_last_good_state.csv.
std::string lastGoodPath(const RunOptions& options);

// What every run keeps after a blow-up: the observables up to the failure (`commitObservables`
// closes the file, when there is one) and the state before the failing step, at lastGoodPath.
void keepAfterInstability(const RunOptions& options, Simulation& sim, const std::function<void()>& commitObservables);

// Returns the exit code.
int runCommand(const RunOptions& options);

}  // namespace corebox
