#include "run_command.h"

#include <cstdio>
#include <iostream>
#include <memory>

#include <filesystem>

#include "atomic_file.h"
#include "errors.h"
#include "frame_dumper.h"
#include "glfw_window.h"
#include "rendered_run.h"
#include "script.h"
#include "initial_conditions.h"
#include "observables.h"
#include "progress.h"
#include "scene_io.h"
#include "simulation.h"
#include "state_csv.h"

namespace corebox {
namespace {

void applyOverrides(const RunOptions& options, Scene& scene) {
    if (options.precision) {
        if (*options.precision == "fp32") scene.integrator.precision = Precision::Fp32;
        else if (*options.precision == "fp64") scene.integrator.precision = Precision::Fp64;
        else throw InputError("--precision: expected fp32 or fp64, got '" + *options.precision + "'");
    }
    if (options.method && !parseMethod(*options.method, &scene.integrator.method)) {
        throw InputError("--method: unknown method '" + *options.method + "' (expected euler, rk2, rk4, dp5, hairer10 or verlet)");
    }
    if (options.method && scene.integrator.adaptive && scene.integrator.method != Method::Dp5) scene.integrator.adaptive = false;
    if (options.dt) {
        if (!(*options.dt > 0)) throw InputError("--dt: must be > 0");
        scene.integrator.dt = *options.dt;
    }
    if (options.seed) {
        if (*options.seed < 0) throw InputError("--seed: must be >= 0");
        scene.init.seed = uint64_t(*options.seed);
    }
}

struct FrameSize {
    int width, height;
};

FrameSize parseSize(const std::string& text) {
    int w = 0, h = 0;
    char x = 0, extra = 0;
    if (std::sscanf(text.c_str(), "%d%c%d%c", &w, &x, &h, &extra) != 3 || (x != 'x' && x != 'X') || w < 16 || h < 16 ||
        w > 16384 || h > 16384) {
        throw InputError("--size: expected WIDTHxHEIGHT with each between 16 and 16384, got '" + text + "'");
    }
    return {w, h};
}

// Checks the headless flags and turns them into run settings: steps, observation interval and the
// observables file inside the output directory (created if missing).
void prepareHeadless(RunOptions& options) {
    HeadlessOptions& h = options.headless;
    if (!h.enabled) return;
    if (h.frames < 1) throw InputError("--frames: must be >= 1 (got " + std::to_string(h.frames) + ")");
    if (h.stepsPerFrame < 1) throw InputError("--steps-per-frame: must be >= 1");
    if (h.outDir.empty()) throw InputError("--headless needs --out DIR for the frames");
    parseSize(h.size);
    if (h.colorBy != "species" && h.colorBy != "speed") throw InputError("--color-by: expected species or speed, got '" + h.colorBy + "'");
    std::error_code ec;
    std::filesystem::create_directories(h.outDir, ec);
    if (ec) throw InputError("--out: cannot create directory '" + h.outDir + "': " + ec.message());
    checkWritable(h.outDir + "/frame_000000.png", "--out");
    if (!h.videoPath.empty()) {
        checkWritable(h.videoPath, "--video");
        try {
            requireFfmpeg();
        } catch (const std::runtime_error& e) {
            throw InputError(e.what());
        }
    }
    options.steps = (h.frames - 1) * h.stepsPerFrame;
    options.every = h.stepsPerFrame;
    if (options.observablesPath.empty()) options.observablesPath = h.outDir + "/observables.csv";
}

void checkOptions(const RunOptions& options) {
    if (options.steps < 0) throw InputError("--steps: must be >= 0");
    if (options.every < 1) throw InputError("--every: must be >= 1");
    if (!(options.maxEnergyDrift > 0)) throw InputError("--max-drift: must be > 0");
    if (!options.observablesPath.empty()) checkWritable(options.observablesPath, "--observables");
    if (!options.stateOutPath.empty()) checkWritable(options.stateOutPath, "--state-out");
}

}  // namespace

std::string lastGoodPath(const RunOptions& options) {
    if (!options.stateOutPath.empty()) {
        std::string base = options.stateOutPath;
        if (base.size() > 4 && base.compare(base.size() - 4, 4, ".csv") == 0) base.resize(base.size() - 4);
        return base + ".last_good.csv";
    }
    if (!options.observablesPath.empty()) {
        const size_t slash = options.observablesPath.find_last_of('/');
        return (slash == std::string::npos ? std::string() : options.observablesPath.substr(0, slash + 1)) + "last_good_state.csv";
    }
    return "corebox_last_good_state.csv";
}

// Without rendering: observables to a file or stdout, progress on stderr.
static int runBatch(const RunOptions& options, const Scene& scene) {
    std::unique_ptr<Simulation> sim;
    std::unique_ptr<AtomicFile> observablesFile;
    try {
        const ParticleState initial = makeInitialState(scene);
        BackendChoice choice = options.backend;
        choice.precision = scene.integrator.precision;
        std::unique_ptr<Backend> backend = makeBackend(choice);
        std::fprintf(stderr, "[corebox] %s: %lld particles, %zu species, %s %s dt = %g, backend %s (%s), %lld steps\n",
                     options.scenePath.c_str(), (long long)initial.size(), scene.species.size(), methodName(scene.integrator.method),
                     precisionName(scene.integrator.precision), scene.integrator.dt, backend->name().c_str(),
                     backend->deviceName().c_str(), (long long)options.steps);
        SimulationLimits limits;
        limits.maxEnergyDrift = options.maxEnergyDrift;
        sim = std::make_unique<Simulation>(scene, std::move(backend), initial, limits);
        if (!options.observablesPath.empty()) observablesFile = std::make_unique<AtomicFile>(options.observablesPath);
    } catch (const InputError& e) {
        std::fprintf(stderr, "corebox: error: %s\n", e.what());
        return kExitInput;
    } catch (const DeviceError& e) {
        std::fprintf(stderr, "corebox: device error: %s\n", e.what());
        return kExitDevice;
    } catch (const InstabilityError& e) {
        std::fprintf(stderr, "corebox: %s\n", e.what());
        return kExitUnstable;
    }

    std::ostream& out = observablesFile ? observablesFile->stream() : std::cout;
    out << observablesHeader(sim->scene()) << '\n';
    ProgressReporter progress(options.steps, !options.quiet);
    const double dof = 3.0 * double(std::max<int64_t>(sim->particleCount(), 1));
    int64_t capHitsReported = 0;
    try {
        writeObservablesRow(out, sim->observe());
        for (int64_t s = 1; s <= options.steps; ++s) {
            sim->step();
            if (s % options.every == 0 || s == options.steps) writeObservablesRow(out, sim->observe());
            if (sim->roundCapHits() > capHitsReported) {
                std::fprintf(stderr, "[corebox] warning: step %lld: overlaps remained after %d collision rounds (%lld steps so far); "
                             "consider a smaller dt or a larger [interaction] max_collision_rounds\n",
                             (long long)s, sim->scene().interaction.maxCollisionRounds, (long long)sim->roundCapHits());
                capHitsReported = sim->roundCapHits() * 2;  // report again only when it keeps happening
            }
            progress.update(s, sim->time(), 2.0 * sim->lastKineticEnergy() / dof);
        }
        progress.finish(options.steps, sim->time(), 2.0 * sim->lastKineticEnergy() / dof);
        if (observablesFile) observablesFile->commit();
        if (!options.stateOutPath.empty()) writeStateCsv(options.stateOutPath, sim->state());
    } catch (const InstabilityError& e) {
        std::fprintf(stderr, "corebox: %s\n", e.what());
        try {
            if (observablesFile) {
                observablesFile->commit();
                std::fprintf(stderr, "corebox: observables up to the failure are in %s\n", options.observablesPath.c_str());
            }
            const std::string path = lastGoodPath(options);
            writeStateCsv(path, sim->lastGoodState());
            std::fprintf(stderr, "corebox: last good state (before step %lld) written to %s\n", (long long)sim->stepIndex(), path.c_str());
        } catch (const InputError& w) {
            std::fprintf(stderr, "corebox: error: %s\n", w.what());
        }
        return kExitUnstable;
    } catch (const InputError& e) {
        std::fprintf(stderr, "corebox: error: %s\n", e.what());
        return kExitInput;
    } catch (const DeviceError& e) {
        std::fprintf(stderr, "corebox: device error: %s\n", e.what());
        return kExitDevice;
    }
    return kExitOk;
}

void reportFrames(const RunOptions& options, FrameDumper& frames) {
    const bool videoOk = frames.finish();
    const FrameTimings& t = frames.timings();
    const double n = double(std::max<int64_t>(t.frames, 1));
    std::fprintf(stderr,
                 "[corebox] %lld frames in %s/ (frame_000000.png ...): %.1f frames/s including simulation and output; per frame "
                 "%.1f ms render, %.1f ms read-back, %.1f ms waiting for PNG encoding (%d encoder threads)\n",
                 (long long)t.frames, options.headless.outDir.c_str(), t.wall > 0 ? double(t.frames) / t.wall : 0.0, 1e3 * t.render / n,
                 1e3 * t.readback / n, 1e3 * t.encodeWait / n, t.encoders);
    if (!options.headless.videoPath.empty()) {
        if (videoOk) std::fprintf(stderr, "[corebox] video written to %s\n", options.headless.videoPath.c_str());
        else throw std::runtime_error("ffmpeg failed to write " + options.headless.videoPath);
    } else {
        std::fprintf(stderr, "[corebox] make a video with: ffmpeg -framerate 30 -i %s/frame_%%06d.png -pix_fmt yuv420p %s/movie.mp4\n",
                     options.headless.outDir.c_str(), options.headless.outDir.c_str());
    }
}


int runCommand(const RunOptions& requested) {
    RunOptions options = requested;
    Scene scene;
    try {
        prepareHeadless(options);
        checkOptions(options);
        scene = loadScene(options.scenePath);
        applyOverrides(options, scene);
        if (!options.scriptPath.empty()) Script::load(options.scriptPath);  // errors before anything runs
        if (!options.screenshotPath.empty()) checkWritable(options.screenshotPath, "--screenshot");
    } catch (const InputError& e) {
        std::fprintf(stderr, "corebox: error: %s\n", e.what());
        return kExitInput;
    }
    if (options.headless.enabled) return runHeadlessFrames(options, scene);
    if (!options.noWindow && GlfwWindow::displayAvailable()) return runWindow(options, scene);
    return runBatch(options, scene);
}

}  // namespace corebox
