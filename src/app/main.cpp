// corebox command line. Subcommands: run (DESIGN.md sec. 3). Usage errors exit with code 2.
#include <CLI/CLI.hpp>

#include <cstdio>

#include "errors.h"

#include "force_benchmark.h"
#include "glfw_window.h"
#include "run_command.h"
#include "throughput_benchmark.h"

int main(int argc, char** argv) {
    using namespace corebox;
    CLI::App app{"corebox: hard-core particles with Lennard-Jones forces in a rigid box"};
    app.set_version_flag("--version", std::string("corebox ") + COREBOX_VERSION);
    app.require_subcommand(0, 1);

    RunOptions run;
    std::string precision, method;
    double dt = 0;
    int64_t seed = -1;
    CLI::App* runCmd = app.add_subcommand("run", "Run a scene and write observables and the final state");
    runCmd->add_option("scene", run.scenePath, "Scene file (TOML), e.g. assets/argon_gas.toml")->required();
    runCmd->add_option("--steps", run.steps, "Number of steps")->capture_default_str();
    runCmd->add_option("--every", run.every, "Observables row every K steps")->capture_default_str();
    runCmd->add_option("--observables", run.observablesPath, "Observables CSV (default: stdout)");
    runCmd->add_option("--state-out", run.stateOutPath, "Write the final state as CSV");
    runCmd->add_option("--backend", run.backend.name, "cpu, cuda or auto")->capture_default_str();
    runCmd->add_option("--threads", run.backend.threads, "CPU threads (0: all cores)")->capture_default_str();
    auto* precisionOpt = runCmd->add_option("--precision", precision, "Override the scene's precision: fp32 or fp64");
    auto* methodOpt = runCmd->add_option("--method", method, "Override the integrator: euler, rk2, rk4, dp5, hairer10, verlet");
    auto* dtOpt = runCmd->add_option("--dt", dt, "Override the time step");
    auto* seedOpt = runCmd->add_option("--seed", seed, "Override the random seed");
    runCmd->add_option("--max-drift", run.maxEnergyDrift,
                       "Stop (exit 3) when the conserved energy moves by more than this fraction of the energy scale")
        ->capture_default_str();
    runCmd->add_flag("--quiet", run.quiet, "No progress lines on stderr");
    HeadlessOptions& h = run.headless;
    runCmd->add_flag("--headless", h.enabled, "Render frames without a display (EGL) into --out");
    runCmd->add_option("--frames", h.frames, "Number of frames (frame 0 is the initial state)");
    runCmd->add_option("--steps-per-frame", h.stepsPerFrame, "Simulation steps between frames")->capture_default_str();
    runCmd->add_option("--size", h.size, "Frame size WIDTHxHEIGHT")->capture_default_str();
    runCmd->add_option("--out", h.outDir, "Directory for frame_NNNNNN.png and observables.csv");
    runCmd->add_option("--color-by", h.colorBy, "species or speed")->capture_default_str();
    runCmd->add_option("--video", h.videoPath, "Also encode the frames into this video file (needs ffmpeg)");
    runCmd->add_option("--speed-max", h.speedMax, "Top of the speed colour bar (default: from the temperature)");
    runCmd->add_flag("--software-gl", h.softwareOnly, "Render on Mesa's software device even when a GPU is present");
    runCmd->add_flag("--hud", h.hud, "Headless: draw the speed histogram, time plots and performance into the frames");
    runCmd->add_option("--script", run.scriptPath, "Timed commands (set, pause, resume, reset, screenshot, quit), window or headless");
    runCmd->add_option("--screenshot", run.screenshotPath, "Save the last frame (window or headless) as PNG");
    runCmd->add_flag("--no-window", run.noWindow, "Batch run (observables only) even where there is a display");

    CLI::App* benchCmd = app.add_subcommand("bench", "Benchmarks that write CSV and JSON results");
    benchCmd->require_subcommand(1);
    ForceBenchmarkOptions forces;
    std::vector<std::string> precisions{"fp32", "fp64"};
    CLI::App* forcesCmd = benchCmd->add_subcommand("forces", "Pair interactions per second of the all-pairs force pass");
    forcesCmd->add_option("--backend", forces.backend, "cpu or cuda")->capture_default_str();
    forcesCmd->add_option("--threads", forces.threads, "CPU threads (0: all cores)")->capture_default_str();
    forcesCmd->add_option("--n", forces.sizes, "Particle counts")->delimiter(',')->capture_default_str();
    forcesCmd->add_option("--precision", precisions, "fp32 and/or fp64")->delimiter(',')->check(CLI::IsMember({"fp32", "fp64"}));
    forcesCmd->add_option("--min-seconds", forces.minSeconds, "Repeat each measurement at least this long")->capture_default_str();
    forcesCmd->add_option("--out", forces.outputPrefix, "Write OUT.csv and OUT.json");

    ThroughputOptions throughput;
    std::vector<std::string> throughputPrecisions{"fp32", "fp64"}, throughputMethods{"euler", "rk2", "rk4", "dp5", "hairer10", "verlet"};
    std::string frameSize = "1920x1080";
    CLI::App* throughputCmd = benchCmd->add_subcommand("throughput", "Force pass, full steps per method, interop and frames");
    throughputCmd->add_option("--backend", throughput.backend, "cpu or cuda")->capture_default_str();
    throughputCmd->add_option("--n-forces", throughput.forceSizes, "Particle counts for the force pass")->delimiter(',')->capture_default_str();
    throughputCmd->add_option("--n-step", throughput.stepN, "Particle count for the full steps")->capture_default_str();
    throughputCmd->add_option("--precision", throughputPrecisions, "fp32 and/or fp64")->delimiter(',')->check(CLI::IsMember({"fp32", "fp64"}));
    throughputCmd->add_option("--methods", throughputMethods, "Integrators for the full steps")->delimiter(',');
    throughputCmd->add_option("--n-frames", throughput.frameN, "Particle count for the frame measurements (0: none)")->capture_default_str();
    throughputCmd->add_option("--size", frameSize, "Frame size WIDTHxHEIGHT")->capture_default_str();
    throughputCmd->add_option("--min-seconds", throughput.minSeconds, "Repeat each measurement at least this long")->capture_default_str();
    throughputCmd->add_option("--out", throughput.outputPrefix, "Write OUT.csv and OUT.json");

    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        const int code = app.exit(e);
        return code == 0 ? 0 : kExitInput;
    }
    if (*precisionOpt) run.precision = precision;
    if (*methodOpt) run.method = method;
    if (*dtOpt) run.dt = dt;
    if (*seedOpt) run.seed = seed;
    if (*runCmd) return runCommand(run);
    if (app.get_subcommands().empty()) {
        // `corebox` alone: the default scene in a window.
        if (!GlfwWindow::displayAvailable()) {
            std::fprintf(stderr, "corebox: no display; try `corebox run SCENE --headless --frames N --out DIR`, see --help\n");
            return kExitInput;
        }
        run.scenePath = COREBOX_DEFAULT_SCENE;
        return runCommand(run);
    }
    if (*throughputCmd) {
        throughput.precisions.clear();
        for (const std::string& p : throughputPrecisions) throughput.precisions.push_back(p == "fp32" ? Precision::Fp32 : Precision::Fp64);
        throughput.methods.clear();
        for (const std::string& m : throughputMethods) {
            Method method;
            if (!parseMethod(m, &method)) {
                std::fprintf(stderr, "corebox: error: --methods: unknown method '%s'\n", m.c_str());
                return kExitInput;
            }
            throughput.methods.push_back(method);
        }
        if (std::sscanf(frameSize.c_str(), "%dx%d", &throughput.frameWidth, &throughput.frameHeight) != 2) {
            std::fprintf(stderr, "corebox: error: --size: expected WIDTHxHEIGHT\n");
            return kExitInput;
        }
        for (int i = 0; i < argc; ++i) throughput.commandLine += (i ? " " : "") + std::string(i ? argv[i] : "corebox");
        try {
            runThroughputBenchmark(throughput);
        } catch (const DeviceError& e) {
            std::fprintf(stderr, "corebox: device error: %s\n", e.what());
            return kExitDevice;
        } catch (const std::exception& e) {
            std::fprintf(stderr, "corebox: error: %s\n", e.what());
            return kExitInput;
        }
        return 0;
    }
    if (*forcesCmd) {
        forces.precisions.clear();
        for (const std::string& p : precisions) forces.precisions.push_back(p == "fp32" ? Precision::Fp32 : Precision::Fp64);
        for (int i = 0; i < argc; ++i) forces.commandLine += (i ? " " : "") + std::string(i ? argv[i] : "corebox");
        try {
            runForceBenchmark(forces);
        } catch (const std::exception& e) {
            std::fprintf(stderr, "corebox: error: %s\n", e.what());
            return kExitInput;
        }
        return 0;
    }
    return kExitInput;
}
