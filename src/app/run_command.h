// `corebox run SCENE ...`: load a scene, run it on a backend, write observables and the final state.
// Exit codes (DESIGN.md sec. 3): 0 ok, 2 usage or input error, 3 instability, 4 device error.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "backend_factory.h"

namespace corebox {

// `--headless`: frames rendered on an EGL context and dumped as PNG (and video).
struct HeadlessOptions {
    bool enabled = false;
    int64_t frames = 0;           // frame 0 is the initial state, then one every stepsPerFrame steps
    int64_t stepsPerFrame = 10;
    std::string size = "1280x720";
    std::string outDir;
    std::string colorBy = "species";  // species | speed
    std::string videoPath;
    double speedMax = 0;          // colour bar top; 0: from the temperature
    bool softwareOnly = false;    // render on Mesa's software device even when a GPU is there
    bool hud = false;             // draw the histogram and plots into the frames
};

struct RunOptions {
    std::string scenePath;
    int64_t steps = 1000;
    int64_t every = 100;               // observables row every K steps (and at step 0 and the end)
    std::string observablesPath;       // "" : rows go to stdout
    std::string stateOutPath;          // "" : final state not written
    BackendChoice backend;
    std::optional<std::string> precision;  // overrides [integrator] precision
    std::optional<std::string> method;     // overrides [integrator] method
    std::optional<double> dt;              // overrides [integrator] dt
    std::optional<int64_t> seed;           // overrides [init] seed
    double maxEnergyDrift = 0.5;
    bool quiet = false;                    // no progress lines
    HeadlessOptions headless;              // frames also bounds a window run
    std::string scriptPath;                // --script: timed commands (window and headless)
    std::string screenshotPath;            // --screenshot: the last frame as PNG
    bool noWindow = false;                 // batch run even where there is a display
};

// Where a run that blew up writes its last good state: beside --state-out (NAME.last_good.csv),
// else beside --observables (last_good_state.csv), else corebox_last_good_state.csv.
std::string lastGoodPath(const RunOptions& options);

class FrameDumper;
// Frame timings and where the frames are (and the video, closed here), on stderr.
void reportFrames(const RunOptions& options, FrameDumper& frames);

enum ExitCode : int { kExitOk = 0, kExitInput = 2, kExitUnstable = 3, kExitDevice = 4 };

int runCommand(const RunOptions& options);

}  // namespace corebox
