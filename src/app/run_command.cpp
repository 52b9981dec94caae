#include "run_command.h"

#include "auto_integrator.h"
#include "study_curves.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>

#include "atomic_file.h"
#include "checkpoint.h"
#include "batch_run.h"
#include "error_report.h"
#include "errors.h"
#include "frame_dumper.h"
#include "glfw_window.h"
#include "rendered_run.h"
#include "scene_io.h"
#include "scene_validation.h"
#include "script.h"
#include "state_csv.h"

namespace corebox {
namespace {

void applyOverrides(const RunOptions& options, Scene& scene) {
    if (options.precision) scene.integrator.precision = *options.precision;
    if (options.method) {
        scene.integrator.method = *options.method;
        scene.integrator.automatic = false;
        if (scene.integrator.adaptive && scene.integrator.method != Method::Dp5) scene.integrator.adaptive = false;
    }
    if (options.dt) {
        if (!(*options.dt > 0) || !std::isfinite(*options.dt)) throw InputError("--dt: must be a finite number > 0");
        scene.integrator.dt = *options.dt;
    }
    if (options.gpus) scene.devices.gpus = *options.gpus;
    if (options.exchange) scene.devices.exchange = *options.exchange;
    if (options.forces) scene.interaction.forces = *options.forces;
    if (options.seed) {
        if (*options.seed < 0) throw InputError("--seed: must be >= 0");
        scene.init.seed = uint64_t(*options.seed);
    }
}

// Checks the headless flags and turns them into run settings: steps, observation interval and the
// observables file inside the output directory (created if missing).
void prepareHeadless(RunOptions& options) {
    HeadlessOptions& h = options.headless;
    if (!h.enabled) return;
    if (!h.framesGiven) throw InputError("--headless needs --frames N: the number of frames to write (frame 0 is the initial state)");
    if (h.frames < 1) throw InputError("--frames: must be >= 1 (got " + std::to_string(h.frames) + ")");
    if (h.stepsPerFrame < 1) throw InputError("--steps-per-frame: must be >= 1");
    if (h.outDir.empty()) throw InputError("--headless needs --out DIR for the frames");
    if (!h.videoPath.empty()) checkVideoPath(h.videoPath);  // before anything is created
    std::error_code ec;
    std::filesystem::create_directories(h.outDir, ec);
    if (ec) throw InputError("--out: cannot create directory '" + h.outDir + "': " + ec.message());
    checkWritable(h.outDir + "/frame_000000.png", "--out");
    if (!h.videoPath.empty()) {
        checkWritable(h.videoPath, "--video");
        requireFfmpeg();
    }
    if (h.frames - 1 > std::numeric_limits<int64_t>::max() / h.stepsPerFrame)
        throw InputError("--frames x --steps-per-frame: more steps than a 64-bit count holds");
    if (options.stepsGiven)
        std::fprintf(stderr, "corebox: warning: --steps is ignored with --headless: the run lasts (frames - 1) x steps-per-frame = "
                             "%lld steps\n", (long long)((h.frames - 1) * h.stepsPerFrame));
    options.steps = (h.frames - 1) * h.stepsPerFrame;
    options.every = h.stepsPerFrame;
    if (options.observablesPath.empty()) options.observablesPath = h.outDir + "/observables.csv";
}

void checkOptions(const RunOptions& options) {
    if (options.restartPath.empty() && options.scenePath.empty()) throw InputError("run: give a SCENE file (or --restart CHECKPOINT)");
    if (!options.restartPath.empty()) {
        if (!options.scenePath.empty())
            throw InputError("--restart: the checkpoint holds the scene; give no SCENE file with it");
        if (options.precision || options.method || options.dt || options.seed)
            throw InputError("--restart: --precision, --method, --dt and --seed would change the run the checkpoint continues; "
                             "they are not allowed with it");
        if (options.headless.enabled || !options.scriptPath.empty())
            throw InputError("--restart: batch runs only (no --headless, no --script)");
    }
    if (!options.checkpointPath.empty()) {
        if (options.headless.enabled) throw InputError("--checkpoint: batch runs only (not with --headless)");
        if (options.checkpointEvery < 0) throw InputError("--checkpoint-every: must be >= 0");
        checkWritable(options.checkpointPath, "--checkpoint");
    }
    if (options.steps < 0) throw InputError("--steps: must be >= 0");
    if (options.every < 1) throw InputError("--every: must be >= 1");
    if (!(options.maxEnergyDrift > 0)) throw InputError("--max-drift: must be > 0");
    if (!options.observablesPath.empty()) checkWritable(options.observablesPath, "--observables");
    if (!options.stateOutPath.empty()) checkWritable(options.stateOutPath, "--state-out");
}

// Every file the run reads and every file it writes: an output must be none of the inputs and no
// other output (atomic_file.h).
void checkOutputsApart(const RunOptions& options, const Scene& scene) {
    std::vector<NamedPath> inputs{{"scene", options.scenePath}, {"init.particles file", scene.init.particlesFile},
                                  {"--script", options.scriptPath}, {"--restart", options.restartPath}};
    std::vector<NamedPath> outputs{{"--observables", options.observablesPath},
                                   {"--state-out", options.stateOutPath},
                                   {"--screenshot", options.screenshotPath},
                                   {"--checkpoint", options.checkpointPath}};
    // Going on from a checkpoint and writing the next ones to the same file is the usual way to run
    // in pieces: the checkpoint is read whole before the run, and the one replaced is kept as .prev.
    std::error_code ec;
    if (!options.restartPath.empty() && !options.checkpointPath.empty() &&
        std::filesystem::equivalent(options.restartPath, options.checkpointPath, ec))
        outputs.pop_back();
    if (options.headless.enabled) {
        outputs.push_back({"--video", options.headless.videoPath});
        outputs.push_back({"--out (its first frame)", FrameDumper::framePath(options.headless.outDir, 0)});
    }
    checkDistinctPaths(inputs, outputs);
}

}  // namespace

std::string lastGoodPath(const RunOptions& options) {
    if (!options.stateOutPath.empty()) {
        std::string base = options.stateOutPath;
        if (base.size() > 4 && base.compare(base.size() - 4, 4, ".csv") == 0) base.resize(base.size() - 4);
        return base + ".last_good.csv";
    }
    if (!options.observablesPath.empty() && inspectOutput(options.observablesPath).kind != OutputKind::Stream) {
        const size_t slash = options.observablesPath.find_last_of('/');
        return (slash == std::string::npos ? std::string() : options.observablesPath.substr(0, slash + 1)) + "last_good_state.csv";
    }
    return "corebox_last_good_state.csv";
}

void keepAfterInstability(const RunOptions& options, Simulation& sim, const std::function<void()>& commitObservables) {
    commitObservables();
    if (!options.observablesPath.empty()) {
        std::fprintf(stderr, "corebox: observables up to the failure are in %s\n", options.observablesPath.c_str());
    }
    const std::string path = lastGoodPath(options);
    writeStateCsv(path, sim.lastGoodState());
    std::fprintf(stderr, "corebox: last good state (before step %lld) written to %s\n", (long long)sim.stepIndex(), path.c_str());
}

int runCommand(const RunOptions& requested) {
    RunOptions options = requested;
    Scene scene;
    const int checked = runReportingErrors([&] {
        prepareHeadless(options);
        checkOptions(options);
        if (options.restartPath.empty()) {
            scene = loadScene(options.scenePath);
        } else {
            scene = parseScene(readCheckpoint(options.restartPath).sceneToml, options.restartPath);
            scene.sourcePath = options.restartPath;
        }
        applyOverrides(options, scene);
        validateScene(scene, SceneLocations(options.scenePath));  // the overrides too (precision changes the bounds)
        if (!options.scriptPath.empty()) Script::load(options.scriptPath);  // errors before anything runs
        if (!options.screenshotPath.empty()) checkWritable(options.screenshotPath, "--screenshot");
        checkOutputsApart(options, scene);
    });
    if (checked != kExitOk) return checked;
    if (scene.integrator.automatic && !options.studyPath.empty()) {
        // A study of the scene answers without a pilot when one of its runs meets the tolerance.
        const int fromStudy = runReportingErrors([&] {
            IntegratorDef chosen;
            std::string why;
            if (chooseIntegratorFromStudy(options.studyPath, scene, &chosen, &why)) {
                scene.integrator = chosen;
                options.integratorChoice = why;
            }
            if (!options.quiet) std::fprintf(stderr, "[corebox] %s%s\n", why.c_str(), scene.integrator.automatic ? "; running a pilot" : "");
        });
        if (fromStudy != kExitOk) return fromStudy;
    }
    if (scene.integrator.automatic) {
        const int resolved = runReportingErrors([&] {
            const BackendChoice choice{options.backend.name, scene.integrator.precision, options.backend.threads, 0};
            scene = resolveAutomaticIntegrator(scene, choice, options.quiet, &options.integratorChoice);
        });
        if (resolved != kExitOk) return resolved;
    }
    if (options.headless.enabled) return runHeadlessFrames(options, scene);
    const bool batchOnly = !options.restartPath.empty() || !options.checkpointPath.empty();
    if (!options.noWindow && !batchOnly && GlfwWindow::displayAvailable()) return runWindow(options, scene);
    // A batch run has no frames to script or to save.
    for (const NamedPath& ignored : {NamedPath{"--script", options.scriptPath}, NamedPath{"--screenshot", options.screenshotPath}}) {
        if (!ignored.path.empty())
            std::fprintf(stderr, "corebox: warning: %s is ignored in a batch run (%s); it acts in a window or with --headless\n",
                         ignored.what.c_str(), options.noWindow ? "--no-window" : "no display");
    }
    return runBatch(options, scene);
}

}  // namespace corebox
