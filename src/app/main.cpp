// corebox command line (DESIGN.md sec. 3): `run`, `bench forces|throughput|md|pile|hardspheres|p2p|table1`, and no subcommand for
// the default scene in a window. Named choices (method, precision, backend, colour mode, frame size)
// are read, checked and listed in --help from their vocabulary tables; every error, the parser's
// own included, leaves through reportError (error_report.h).
#include <CLI/CLI.hpp>

#include <functional>
#include <string>
#include <vector>

#include "display_vocabulary.h"
#include "error_report.h"
#include "errors.h"
#include "force_benchmark.h"
#include "hard_sphere_benchmark.h"
#include "glfw_window.h"
#include "interruption.h"
#include "option_guards.h"
#include "p2p_benchmark.h"
#include "pile_benchmark.h"
#include "run_command.h"
#include "study.h"
#include "table1_benchmark.h"
#include "throughput_benchmark.h"
#include "md_benchmark.h"

namespace corebox {
namespace {

// Accepts the names of `table`; rejects anything else with the table's "unknown ..." message.
template <class Enum>
CLI::Validator oneOf(const Vocabulary<Enum>& table) {
    return CLI::Validator(
        [&table](std::string& text) {
            Enum value;
            return table.parse(text, &value) ? std::string() : table.unknown(text);
        },
        "", table.what());
}

// An option taking one name of `table`, stored through `set` once checked.
template <class Enum>
CLI::Option* addChoice(CLI::App* command, const std::string& flag, const Vocabulary<Enum>& table, const std::string& help,
                       std::function<void(Enum)> set) {
    return command
        ->add_option_function<std::string>(
            flag,
            [&table, set](const std::string& text) {
                Enum value;
                if (table.parse(text, &value)) set(value);
            },
            help + ": one of " + table.list())
        ->check(oneOf(table));
}

// An option taking names of `table` separated by commas; the default shows `values`.
template <class Enum>
CLI::Option* addChoices(CLI::App* command, const std::string& flag, const Vocabulary<Enum>& table, const std::string& help,
                        std::vector<Enum>& values) {
    std::string defaults;
    for (Enum value : values) defaults += (defaults.empty() ? "" : ",") + std::string(table.name(value));
    return command
        ->add_option_function<std::vector<std::string>>(
            flag,
            [&table, &values](const std::vector<std::string>& names) {
                values.clear();
                for (const std::string& name : names) {
                    Enum value;
                    if (table.parse(name, &value)) values.push_back(value);
                }
            },
            help + ", separated by commas: from " + table.list())
        ->delimiter(',')
        ->check(oneOf(table))
        ->default_str(defaults);
}

CLI::Option* addFrameSize(CLI::App* command, FrameSize& size) {
    return command
        ->add_option_function<std::string>(
            "--size", [&size](const std::string& text) { parseFrameSize(text, &size); }, "Frame size WIDTHxHEIGHT")
        ->check(CLI::Validator(
            [](std::string& text) {
                FrameSize ignored;
                return parseFrameSize(text, &ignored) ? std::string() : frameSizeProblem(text);
            },
            "", "frame size"))
        ->default_str(frameSizeName(size));
}

std::string commandLine(int argc, char** argv) {
    std::string out = "corebox";
    for (int i = 1; i < argc; ++i) out += " " + std::string(argv[i]);
    return out;
}

}  // namespace
}  // namespace corebox

int main(int argc, char** argv) {
    using namespace corebox;
    ignoreBrokenPipes();
    CLI::App app{"corebox: hard-core particles with Lennard-Jones forces in a rigid box"};
    app.set_version_flag("--version", std::string("corebox ") + COREBOX_VERSION);
    app.require_subcommand(0, 1);

    RunOptions run;
    double dt = 0;
    int64_t seed = -1;
    CLI::App* runCmd = app.add_subcommand("run", "Run a scene and write observables and the final state");
    runCmd->add_option("scene", run.scenePath, "Scene file (TOML), e.g. assets/argon_gas.toml (not with --restart)");
    auto* stepsOpt = runCmd->add_option("--steps", run.steps, "Number of steps (batch and window runs; --headless: from --frames)")
                         ->capture_default_str();
    runCmd->add_option("--every", run.every, "Observables row every K steps")->capture_default_str();
    runCmd->add_option("--observables", run.observablesPath, "Observables CSV (default: stdout)");
    runCmd->add_option("--state-out", run.stateOutPath, "Write the final state as CSV");
    runCmd->add_option("--backend", run.backend.name, "Backend: one of " + backendTable().list())
        ->check(oneOf(backendTable()))
        ->capture_default_str();
    runCmd->add_option("--threads", run.backend.threads, "CPU threads (0: all cores)")->capture_default_str();
    runCmd->add_option_function<std::string>(
              "--gpus",
              [&](const std::string& text) {
                  if (text == "auto") run.gpus = 0;
                  else run.gpus = std::stoi(text);
              },
              "CUDA: GPUs to spread the particles over, 1 .. the GPUs visible, or auto (the default, or the scene's "
              "[devices] gpus): one GPU below the measured crossover in N, more above it")
        ->check(CLI::Validator(
            [](std::string& text) {
                if (text == "auto") return std::string();
                try {
                    size_t used = 0;
                    const int p = std::stoi(text, &used);
                    if (used == text.size() && p >= 1) return std::string();
                } catch (const std::exception&) {
                }
                return "--gpus: '" + text + "' is not a GPU count (1, 2, ...) or auto";
            },
            "P|auto", "gpu count"));
    addChoice<Exchange>(runCmd, "--exchange", exchangeTable(),
                        "CUDA with several GPUs: how they share positions before each force pass: dts (synchronous peer copies), "
                        "dta (asynchronous peer copies), da (kernels read peer memory; neighbour lists are then not used, every pair is "
                        "computed), nccl (all-gather); auto: the fastest measured",
                        [&](Exchange e) { run.exchange = e; });
    addChoice<ForceModel>(runCmd, "--forces", forceModelTable(),
                          "Override the scene's [interaction] forces: auto (the cheapest model that serves the scene), all_pairs, "
                          "neighbour_list (needs a cutoff)",
                          [&](ForceModel f) { run.forces = f; });
    addChoice<Precision>(runCmd, "--precision", precisionTable(), "Override the scene's precision",
                         [&](Precision p) { run.precision = p; });
    addChoice<Method>(runCmd, "--method", methodTable(), "Override the integrator", [&](Method m) { run.method = m; });
    auto* dtOpt = runCmd->add_option("--dt", dt, "Override the time step");
    auto* seedOpt = runCmd->add_option("--seed", seed, "Override the random seed");
    runCmd->add_option("--max-drift", run.maxEnergyDrift,
                       "Stop (exit 3) when the conserved energy moves by more than this fraction of the energy scale")
        ->capture_default_str();
    runCmd->add_option("--study", run.studyPath,
                       "A study file of the scene (corebox study SCENE --out PREFIX writes PREFIX.json): method = \"auto\" takes "
                       "its cheapest run that meets the tolerance instead of a pilot, and the window's speed-vs-accuracy panel draws "
                       "its lines under the running simulation's points (default for the panel: "
                       "docs/results/study_<scene>_<cpu|h200>.json beside the scene's directory, when there is one)")
        ->check(CLI::ExistingFile);
    runCmd->add_flag("--recover", run.recover,
                     "Batch and headless runs: after a blow-up go back to the last good state (the last observables row), "
                     "halve dt and go on (the window always does), instead of stopping with exit code 3");
    runCmd->add_flag("--quiet", run.quiet, "Only warnings and errors on stderr (no start line, progress or summary)");
    HeadlessOptions& h = run.headless;
    runCmd->add_flag("--headless", h.enabled, "Render frames without a display (EGL) into --out");
    auto* framesOpt = runCmd->add_option("--frames", h.frames, "Number of frames (frame 0 is the initial state); required with --headless");
    runCmd->add_option("--steps-per-frame", h.stepsPerFrame, "Simulation steps between frames")->capture_default_str();
    addFrameSize(runCmd, h.size);
    runCmd->add_option("--out", h.outDir, "Directory for frame_NNNNNN.png and observables.csv");
    addChoice<ColorMode>(runCmd, "--color-by", colorModeTable(), "Particle colours", [&](ColorMode m) { h.colorBy = m; })
        ->default_str(colorModeTable().name(h.colorBy));
    runCmd->add_option("--video", h.videoPath, "Also encode the frames into this video file (needs ffmpeg)");
    runCmd->add_option("--speed-max", h.speedMax, "Top of the speed colour bar (default: from the temperature)");
    runCmd->add_flag("--software-gl", h.softwareOnly, "Render on Mesa's software device even when a GPU is present");
    runCmd->add_flag_callback("--no-png", [&h] { h.writePng = false; }, "Headless: render every frame but write no PNG (a frame-rate run; --video and --screenshot still work)");
    runCmd->add_flag("--hud", h.hud, "Headless: draw the speed histogram, time plots and performance into the frames");
    runCmd->add_option("--script", run.scriptPath, "Timed commands (set, pause, resume, reset, screenshot, quit), window or headless");
    runCmd->add_option("--screenshot", run.screenshotPath, "Save the last frame (window or headless) as PNG");
    runCmd->add_flag("--no-window", run.noWindow, "Batch run (observables only) even where there is a display");
    runCmd->add_option("--checkpoint", run.checkpointPath,
                       "Batch runs: write a checkpoint to this file (atomically, the previous one kept as FILE.prev) at the "
                       "end, on interruption and every --checkpoint-every steps");
    runCmd->add_option("--checkpoint-every", run.checkpointEvery, "Steps between checkpoints (0: only at the end and on interruption)")
        ->capture_default_str();
    runCmd->add_option("--restart", run.restartPath,
                       "Batch runs: go on from a checkpoint (its scene, state, step and bookkeeping) up to --steps in all; "
                       "bit-identical to a run that never stopped on the same backend and precision");

    CLI::App* benchCmd = app.add_subcommand("bench", "Benchmarks that write CSV and JSON results");
    benchCmd->require_subcommand(1);
    ForceBenchmarkOptions forces;
    CLI::App* forcesCmd = benchCmd->add_subcommand("forces", "Pair interactions per second of the all-pairs force pass");
    forcesCmd->add_option("--backend", forces.backend, "Backend: one of " + backendTable().list())
        ->check(oneOf(backendTable()))
        ->capture_default_str();
    forcesCmd->add_option("--threads", forces.threads, "CPU threads (0: all cores)")->capture_default_str();
    forcesCmd->add_option("--n", forces.sizes, "Particle counts")->delimiter(',')->capture_default_str();
    addChoices(forcesCmd, "--precision", precisionTable(), "Precisions", forces.precisions);
    forcesCmd->add_option("--min-seconds", forces.minSeconds, "Repeat each measurement at least this long")->capture_default_str();
    forcesCmd->add_option("--out", forces.outputPrefix, "Write OUT.csv and OUT.json");
    forcesCmd->add_option("--gpus", forces.gpus, "CUDA: GPU counts sharing the pass, e.g. 1,2 (each P its own run)")
        ->delimiter(',')
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    std::vector<std::string> forceKernels{"pairs_once", "ordered"};
    forcesCmd
        ->add_option("--kernels", forceKernels,
                     "CUDA all-pairs kernels to measure: pairs_once (each pair once, Newton's third law, where it applies; "
                     "the ordered kernel runs where it does not) and ordered (every ordered pair)")
        ->delimiter(',')
        ->check(CLI::IsMember({"pairs_once", "ordered"}))
        ->capture_default_str();

    ThroughputOptions throughput;
    FrameSize frameSize{throughput.frameWidth, throughput.frameHeight};
    CLI::App* throughputCmd = benchCmd->add_subcommand("throughput", "Force pass, full steps per method, interop and frames");
    throughputCmd->add_option("--backend", throughput.backend, "Backend: one of " + backendTable().list())
        ->check(oneOf(backendTable()))
        ->capture_default_str();
    throughputCmd->add_option("--n-forces", throughput.forceSizes, "Particle counts for the force pass")->delimiter(',')->capture_default_str();
    throughputCmd->add_option("--n-step", throughput.stepN, "Particle count for the full steps")->capture_default_str();
    addChoices(throughputCmd, "--precision", precisionTable(), "Precisions", throughput.precisions);
    addChoices(throughputCmd, "--methods", methodTable(), "Integrators for the full steps", throughput.methods);
    throughputCmd->add_option("--n-frames", throughput.frameN, "Particle count for the frame measurements (0: none)")->capture_default_str();
    addFrameSize(throughputCmd, frameSize);
    throughputCmd->add_option("--min-seconds", throughput.minSeconds, "Repeat each measurement at least this long")->capture_default_str();
    throughputCmd->add_option("--out", throughput.outputPrefix, "Write OUT.csv and OUT.json");

    MdBenchmarkOptions md;
    CLI::App* mdCmd = benchCmd->add_subcommand(
        "md", "Cut-off LJ fluid (rho 0.8, T 1.5, r_c 2.5, Verlet, walls): steps/s over N, neighbour lists beside all pairs, and "
              "LAMMPS on the same starting state when lmp is installed");
    mdCmd->add_option("--backend", md.backend, "Backend: one of " + backendTable().list())->check(oneOf(backendTable()))->capture_default_str();
    mdCmd->add_option("--threads", md.threads, "CPU threads (0: all cores)")->capture_default_str();
    mdCmd->add_option("--sizes", md.sizes, "Particle counts")->delimiter(',')->capture_default_str();
    addChoices(mdCmd, "--precision", precisionTable(), "Precisions", md.precisions);
    addChoices(mdCmd, "--forces", forceModelTable(), "Force models (all_pairs, neighbour_list)", md.forces);
    mdCmd->add_option("--min-seconds", md.minSeconds, "Time each configuration at least this long")->capture_default_str();
    mdCmd->add_option("--cpu-max-n", md.cpuMaxN, "Largest N the CPU backend runs (larger: GPU only)")->capture_default_str();
    mdCmd->add_option("--max-seconds", md.maxSeconds, "Skip a configuration predicted to need longer than this")->capture_default_str();
    mdCmd->add_option("--lammps", md.lammps, "LAMMPS binary, auto (lmp on PATH, CPU backend only) or off")->capture_default_str();
    mdCmd->add_option("--lammps-ranks", md.lammpsRanks, "MPI ranks for LAMMPS")->capture_default_str();
    mdCmd->add_option("--out", md.outputPrefix, "Write OUT.csv and OUT.json");

    PileBenchmarkOptions pile;
    CLI::App* pileCmd = benchCmd->add_subcommand(
        "pile", "Balls dropped into a box (assets/pile.toml at N balls): ms per 1/60 s frame, overlap, energy, "
                "time to rest; Bullet beside the CPU backend");
    pileCmd->add_option("--backend", pile.backend, "Backend: one of " + backendTable().list())
        ->check(oneOf(backendTable()))
        ->capture_default_str();
    pileCmd->add_option("--n", pile.sizes, "Ball counts (default: 2000,10000,40000 on cpu; 10^4,10^5,10^6 on cuda)")
        ->delimiter(',')
        ->check(CLI::PositiveNumber);
    addChoices(pileCmd, "--precision", precisionTable(), "Precisions", pile.precisions);
    pileCmd->add_option("--seconds", pile.seconds, "Simulated time per run")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    pileCmd->add_option("--substeps", pile.substeps, "Steps per 1/60 s frame (dt = 1/(60 substeps))")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    pileCmd->add_option("--contact-sweeps", pile.contactSweeps,
                        "The scene's [interaction] contact_sweeps: cap on contact sweeps per listing (0: the backend's own)")
        ->check(CLI::NonNegativeNumber)
        ->capture_default_str();
    pileCmd->add_option("--max-rounds", pile.roundCap,
                        "The scene's [interaction] max_collision_rounds: cap on impact rounds per step (0: the scene's own, 64)")
        ->check(CLI::NonNegativeNumber)
        ->capture_default_str();
    pileCmd->add_option("--threads", pile.threads, "CPU threads (0: all cores)")->capture_default_str();
    pileCmd->add_option("--bullet", pile.bulletPath,
                        "The Bullet driver (default: corebox_bullet_pile beside corebox when built; none: no Bullet)");
    pileCmd->add_option("--out", pile.outputPrefix, "Write OUT.csv and OUT.json");
    pileCmd->add_option("--trace", pile.tracePrefix,
                        "Write TRACE_<backend>_<precision>_<n>.csv: a row per frame with rounds, sweeps, listings, the largest "
                        "overlap left and the host-clock ms of the impacts, contacts and listings");

    P2pBenchmarkOptions p2p;
    CLI::App* p2pCmd = benchCmd->add_subcommand(
        "p2p", "The report's Figure 5: transfer time between GPUs against size for DT-S, DT-A, DA and NCCL");
    p2pCmd->footer(
        "Every GPU j fetches the buffer of GPU (j+1) mod P at the same time, by dts (cudaMemcpyPeer, blocking, "
        "issued GPU after GPU), dta (cudaMemcpyPeerAsync on per-GPU streams, completion by events), da (a kernel on "
        "the receiving GPU reads the peer's buffer over unified addressing) or nccl (ncclAllGather in one group, each "
        "GPU contributing the size). One repeat is timed by the host clock from cudaDeviceSynchronize on every GPU to "
        "the completion of every GPU's part; the median of --repeats after --warmup is reported, with the bandwidth "
        "per GPU. Without peer access between two GPUs, da is refused (recorded with the reason) and dts/dta go "
        "through host memory (cudaMemcpyPeer does that by itself; the path column says so). NCCL_NVLS_ENABLE is set "
        "to 0 unless already set. Needs 2 or more GPUs: exit code 4 otherwise.\n"
        "Example: corebox bench p2p --out docs/results/p2p_h200x2   (then scripts/plot_p2p.py)");
    p2pCmd->add_option("--gpus", p2p.gpus, "GPUs 0..P-1 taking part (0: every GPU CUDA sees; at least 2)")->capture_default_str();
    p2pCmd->add_option("--min-bytes", p2p.minBytes, "Smallest transfer per GPU, a power of two (4096, 4KiB, ...)")
        ->transform(CLI::AsSizeValue(false))
        ->capture_default_str();
    p2pCmd->add_option("--max-bytes", p2p.maxBytes,
                       "Largest transfer per GPU (2147483648, 2GiB, 512MiB, ...); sizes double from --min-bytes up to it. "
                       "Each GPU holds a source of this size and P times it for the all-gather")
        ->transform(CLI::AsSizeValue(false))
        ->capture_default_str();
    p2pCmd->add_option("--repeats", p2p.repeats, "Timed repeats per method and size (the median is reported)")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    p2pCmd->add_option("--warmup", p2p.warmup, "Untimed repeats before them")->check(CLI::NonNegativeNumber)->capture_default_str();
    addChoices(p2pCmd, "--methods", exchangeTable(), "Transfer methods (not auto)", p2p.methods);
    p2pCmd->add_option("--out", p2p.outputPrefix, "Write OUT.csv and OUT.json (with GPUs, driver, topology and the command)");

    Table1Options table1;
    CLI::App* table1Cmd = benchCmd->add_subcommand(
        "table1", "The report's Table 1: ms per RK4 step for every N, GPU count and exchange method");
    table1Cmd->footer(
        "The report's model at a fixed density it does not state: one LJ species, all pairs, hard cores of radius "
        "0.56, number density 0.5, T = 1.5, dt = 1e-3, no thermostat, RK4 with collisions (the scene of bench "
        "throughput). Each configuration (N, precision, P, exchange; P = 1 once, with no exchange) is a fresh "
        "simulation built as corebox run builds it; --warmup steps, then --batches batches of about --batch-seconds "
        "each, ended by the backend's finish(); the median ms per step is reported with the speed-up and efficiency "
        "against P = 1, pair interactions per second (N^2 per force pass, 4 passes per step) and the report's ms per "
        "step on 4 x Tesla C2070 for the same N (report_dts_ms, report_dta_ms, report_da_ms). A configuration that "
        "fails (da without peer access, a device error) is a row with its message and the benchmark goes on. Needs "
        "a GPU, and as many as the largest of --gpus-list: exit code 4 otherwise.\n"
        "Example: corebox bench table1 --out docs/results/table1_h200x2   (then scripts/plot_table1.py)");
    table1Cmd->add_option("--sizes", table1.sizes, "Particle counts; add 262144,1000000 for the large rows")
        ->delimiter(',')
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    table1Cmd->add_option("--gpus-list", table1.gpusList, "GPU counts P to run, e.g. 1,2 (default: 1 up to every GPU CUDA sees)")
        ->delimiter(',')
        ->check(CLI::PositiveNumber);
    addChoices(table1Cmd, "--exchanges", exchangeTable(), "Exchange methods for P > 1 (not auto)", table1.exchanges);
    addChoices(table1Cmd, "--precision", precisionTable(), "Precisions", table1.precisions);
    table1Cmd->add_option("--warmup", table1.warmup, "Untimed steps per configuration; the last one sets the batch length")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    table1Cmd->add_option("--batches", table1.batches, "Timed batches per configuration (the median is reported)")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    table1Cmd->add_option("--batch-seconds", table1.batchSeconds, "Aimed length of one batch; steps per batch follow from the warm-up")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    table1Cmd->add_option("--max-batch-steps", table1.maxBatchSteps, "Most steps in one batch")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    table1Cmd->add_option("--out", table1.outputPrefix, "Write OUT.csv and OUT.json (with GPUs, driver, topology and the command)");

    HardSphereBenchmarkOptions spheres;
    CLI::App* spheresCmd = benchCmd->add_subcommand(
        "hardspheres", "Elastic hard-sphere fluid at several packing fractions: Z against Carnahan-Starling, collision rate "
                       "against Enskog, energy drift, steps/s");
    spheresCmd->add_option("--backend", spheres.backend, "Backend: one of " + backendTable().list())
        ->check(oneOf(backendTable()))
        ->capture_default_str();
    spheresCmd->add_option("--n", spheres.n, "Spheres (default: 2000 on cpu, 50000 on cuda)")->check(CLI::PositiveNumber);
    spheresCmd->add_option("--phi", spheres.packingFractions, "Packing fractions over the box, N pi / (6 L^3)")
        ->delimiter(',')
        ->capture_default_str();
    addChoice<Precision>(spheresCmd, "--precision", precisionTable(), "Precision", [&](Precision p) { spheres.precision = p; })
        ->default_str(precisionTable().name(spheres.precision));
    spheresCmd->add_option("--steps", spheres.steps, "Measured steps per packing fraction (default: 8 tau worth)")
        ->check(CLI::PositiveNumber);
    spheresCmd->add_option("--equilibrate", spheres.equilibrate, "Simulated time before measuring [tau]")->capture_default_str();
    spheresCmd->add_option("--collisions-per-step", spheres.collisionsPerStep, "Sets dt: Enskog collisions per particle per step")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    spheresCmd->add_option("--sample-every", spheres.sampleEvery, "Bulk sample every K steps (default: 1 on cpu, 10 on cuda)")
        ->check(CLI::PositiveNumber);
    spheresCmd->add_option("--margin", spheres.margin,
                           "Bulk region: diameters inside the region open to centres (default: 3 below phi 0.4, 5 from it)");
    spheresCmd->add_option("--seed", spheres.seed, "Initial velocities' seed")->capture_default_str();
    spheresCmd->add_option("--threads", spheres.threads, "CPU threads (0: all cores)")->capture_default_str();
    spheresCmd->add_option("--out", spheres.outputPrefix, "Write OUT.csv and OUT.json");

    StudyOptions study;
    CLI::App* studyCmd = app.add_subcommand(
        "study", "Speed against accuracy on one scene: every method over a ladder of dt in fp64 and fp32 (state error at a short "
                 "horizon against a Hairer 10 reference, energy error over a long run, force passes and wall time per unit time, "
                 "largest stable dt), CSV and JSON");
    studyCmd->add_option("scene", study.scenePath, "Scene file (TOML)")->required()->check(CLI::ExistingFile);
    studyCmd->add_option("--backend", study.backend, "Backend: one of " + backendTable().list())
        ->check(oneOf(backendTable()))
        ->capture_default_str();
    studyCmd->add_option("--threads", study.threads, "CPU threads (0: all cores)")->capture_default_str();
    addChoices(studyCmd, "--methods", methodTable(), "Methods (default: every one)", study.methods);
    addChoices(studyCmd, "--precision", precisionTable(), "Precisions", study.precisions);
    studyCmd->add_option("--dt", study.dtFactors, "The ladder: steps as multiples of the scene's dt")->delimiter(',')->capture_default_str();
    studyCmd->add_option("--tolerances", study.tolerances, "Adaptive dp5 tolerances")->delimiter(',')->capture_default_str();
    studyCmd->add_option("--horizon", study.horizon, "Short horizon T of the state error [tau] (default: 100 of the scene's steps)")
        ->check(CLI::PositiveNumber);
    studyCmd->add_option("--long", study.longRun, "Long run L of the energy error and of each stability trial [tau] (default: 10 T)")
        ->check(CLI::PositiveNumber);
    studyCmd->add_option("--drift-limit", study.driftLimit,
                         "Stability trials fail when the conserved sum moves by more than this fraction of the energy scale")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    studyCmd->add_flag("--no-stability", [&](int64_t) { study.stability = false; }, "Skip the search for each method's largest stable dt");
    studyCmd->add_flag("--quiet", study.quiet, "No progress or summary on stderr");
    studyCmd->add_option("--out", study.outputPrefix, "Write OUT.csv and OUT.json");

    addIntegerRangeChecks(app);
    try {
        app.parse(argc, argv);
    } catch (const CLI::Success& e) {  // --help, --version
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        return reportError(std::make_exception_ptr(InputError(std::string(e.what()) + " (see corebox --help)")));
    }
    for (int* threads : {&run.backend.threads, &forces.threads, &pile.threads, &spheres.threads, &study.threads})
        *threads = capThreads(*threads, "--threads");
    run.stepsGiven = stepsOpt->count() > 0;
    run.headless.framesGiven = framesOpt->count() > 0;
    if (*dtOpt) run.dt = dt;
    if (*seedOpt) run.seed = seed;
    if (*runCmd) {
        installInterruptHandlers();
        return runCommand(run);
    }
    if (app.get_subcommands().empty()) {
        // `corebox` alone: the default scene in a window.
        if (!GlfwWindow::displayAvailable()) {
            return reportError(std::make_exception_ptr(
                InputError("no display; try `corebox run SCENE --headless --frames N --out DIR`, see --help")));
        }
        run.scenePath = COREBOX_DEFAULT_SCENE;
        installInterruptHandlers();
        return runCommand(run);
    }
    if (*throughputCmd) {
        throughput.frameWidth = frameSize.width;
        throughput.frameHeight = frameSize.height;
        throughput.commandLine = commandLine(argc, argv);
        return runReportingErrors([&] { runThroughputBenchmark(throughput); });
    }
    if (*mdCmd) {
        md.commandLine = commandLine(argc, argv);
        return runReportingErrors([&] { runMdBenchmark(md); });
    }
    if (*spheresCmd) {
        spheres.commandLine = commandLine(argc, argv);
        return runReportingErrors([&] { runHardSphereBenchmark(spheres); });
    }
    if (*pileCmd) {
        pile.commandLine = commandLine(argc, argv);
        return runReportingErrors([&] { runPileBenchmark(pile); });
    }
    if (*p2pCmd) {
        p2p.commandLine = commandLine(argc, argv);
        return runReportingErrors([&] { runP2pBenchmark(p2p); });
    }
    if (*table1Cmd) {
        table1.commandLine = commandLine(argc, argv);
        return runReportingErrors([&] { runTable1Benchmark(table1); });
    }
    if (*studyCmd) {
        study.commandLine = commandLine(argc, argv);
        return runReportingErrors([&] { runStudyCommand(study); });
    }
    if (*forcesCmd) {
        forces.commandLine = commandLine(argc, argv);
        forces.pairsOnce.clear();
        for (const std::string& k : forceKernels) forces.pairsOnce.push_back(k == "pairs_once");
        return runReportingErrors([&] { runForceBenchmark(forces); });
    }
    return kExitInput;
}
