#include "md_benchmark.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>

#include "backend_factory.h"
#include "bench_scenes.h"
#include "gpu_records.h"
#include "hardware_info.h"
#include "initial_conditions.h"
#include "lammps_peer.h"
#include "simulation.h"

namespace corebox {
namespace {

using Clock = std::chrono::steady_clock;
double seconds(Clock::time_point since) { return std::chrono::duration<double>(Clock::now() - since).count(); }

constexpr int kWarmupSteps = 3;

// The host's load averages (/proc/loadavg): on a shared machine the other work is part of the record.
std::string loadAverage() {
    std::ifstream in("/proc/loadavg");
    std::string one, five, fifteen;
    if (!(in >> one >> five >> fifteen)) return "";
    return one + " " + five + " " + fifteen;
}

struct Record {
    std::string code;  // corebox | lammps
    std::string backend, precision, forces;
    int64_t n = 0;
    int64_t steps = 0;
    double secondsPerStep = 0;
    double listBuildsPerStep = 0;
    double forcePassesPerStep = 0;
    double msForces = 0, msCollide = 0;  // per step, from the step reports (corebox)
    double stepsPerSecond() const { return secondsPerStep > 0 ? 1.0 / secondsPerStep : 0; }
    double particleStepsPerSecond() const { return double(n) * stepsPerSecond(); }
};

Record measure(const MdBenchmarkOptions& o, int64_t n, Precision p, ForceModel forces, const ParticleState& initial, std::string* device) {
    const Scene scene = mdScene(n, p, forces);
    SimulationLimits limits;
    limits.maxEnergyDrift = 1e9;  // timing only
    Simulation sim(scene, makeBackend(BackendChoice{o.backend, p, o.threads, 0}), initial, limits);
    if (device->empty()) *device = sim.backend().deviceName();
    for (int s = 0; s < kWarmupSteps; ++s) sim.step();
    const ForceCounters before = sim.backend().forceCounters();
    Record r{"corebox", o.backend, precisionName(p), forceModelName(sim.forceChoice().model), n};
    // The time per step without the phase marks (on a GPU, launches of their own)...
    sim.setPhaseTiming(false);
    const Clock::time_point start = Clock::now();
    double t = 0;
    do {
        sim.step();
        ++r.steps;
        t = seconds(start);
    } while (t < o.minSeconds || r.steps < 3);
    sim.backend().finish();
    t = seconds(start);
    const ForceCounters after = sim.backend().forceCounters();
    r.secondsPerStep = t / double(r.steps);
    r.listBuildsPerStep = double(after.listBuilds - before.listBuilds) / double(r.steps);
    r.forcePassesPerStep = double(after.fullPasses - before.fullPasses) / double(r.steps);
    // ...and where it goes, from the marks of the steps that follow (a quarter as many, at least 3).
    sim.setPhaseTiming(true);
    const int64_t phaseSteps = std::max<int64_t>(3, r.steps / 4);
    double forceSeconds = 0, collideSeconds = 0;
    for (int64_t s = 0; s < phaseSteps; ++s) {
        const StepReport report = sim.step();
        forceSeconds += report.secondsForces;
        collideSeconds += report.secondsCollide;
    }
    r.msForces = 1e3 * forceSeconds / double(phaseSteps);
    r.msCollide = 1e3 * collideSeconds / double(phaseSteps);
    return r;
}

// Steps for LAMMPS: a few seconds at its expected rate (~0.4 us per particle-step on two cores).
int64_t lammpsSteps(int64_t n) { return std::max<int64_t>(50, std::min<int64_t>(2000, int64_t(2e7 / double(n)))); }

}  // namespace

void runMdBenchmark(const MdBenchmarkOptions& o) {
    std::vector<Record> records;
    std::string device;
    const std::string loadBefore = loadAverage();
    const std::string lmp = o.backend == "cpu" ? findLammps(o.lammps) : "";
    if (o.backend == "cpu" && o.lammps != "off" && lmp.empty())
        std::fprintf(stderr, "[corebox] LAMMPS not found (lmp on PATH): the peer column stays empty; see docs/md_benchmark.md\n");
    std::string lammpsVersion;
    std::map<std::pair<std::string, std::string>, std::pair<int64_t, double>> lastTime;  // (precision, forces) -> (n, s/step)
    for (int64_t n : o.sizes) {
        if (o.backend == "cpu" && n > o.cpuMaxN) {
            std::fprintf(stderr, "[corebox] md cpu N = %lld: skipped, GPU only (above --cpu-max-n %lld: minutes per configuration on a few cores)\n",
                         (long long)n, (long long)o.cpuMaxN);
            continue;
        }
        Scene base = mdScene(n, Precision::Fp64, ForceModel::AllPairs);
        const ParticleState initial = makeInitialState(base);
        for (Precision p : o.precisions) {
            for (ForceModel f : o.forces) {
                const auto key = std::make_pair(std::string(precisionName(p)), std::string(forceModelName(f)));
                const auto last = lastTime.find(key);
                if (last != lastTime.end()) {
                    const double ratio = double(n) / double(last->second.first);
                    const double predicted = last->second.second * (f == ForceModel::AllPairs ? ratio * ratio : ratio) * (kWarmupSteps + 3);
                    if (predicted > o.maxSeconds) {
                        std::fprintf(stderr, "[corebox] md %s %s %s N = %lld: skipped, predicted %.0f s for %d steps (--max-seconds %.0f)\n",
                                     o.backend.c_str(), key.first.c_str(), key.second.c_str(), (long long)n, predicted, kWarmupSteps + 3,
                                     o.maxSeconds);
                        continue;
                    }
                }
                try {
                    const Record r = measure(o, n, p, f, initial, &device);
                    lastTime[key] = {n, r.secondsPerStep};
                    records.push_back(r);
                    std::fprintf(stderr,
                                 "[corebox] md %s %s %s N = %lld: %.3f ms/step, %.4g steps/s, %.4g particle-steps/s (forces %.3f ms, "
                                 "collisions %.3f ms, %.3f list builds per step)\n",
                                 o.backend.c_str(), r.precision.c_str(), r.forces.c_str(), (long long)n, 1e3 * r.secondsPerStep,
                                 r.stepsPerSecond(), r.particleStepsPerSecond(), r.msForces, r.msCollide, r.listBuildsPerStep);
                } catch (const std::exception& e) {
                    std::fprintf(stderr, "[corebox] md %s %s %s N = %lld: skipped: %s\n", o.backend.c_str(), key.first.c_str(),
                                 key.second.c_str(), (long long)n, e.what());
                }
            }
        }
        if (!lmp.empty()) {
            const double predicted = 1e-6 * double(n) * double(lammpsSteps(n));
            if (predicted > o.maxSeconds) {
                std::fprintf(stderr, "[corebox] md LAMMPS N = %lld: skipped (predicted %.0f s)\n", (long long)n, predicted);
                continue;
            }
            if (const std::optional<LammpsTiming> t = runLammps(lmp, o.lammpsRanks, base, initial, lammpsSteps(n))) {
                lammpsVersion = t->version;
                Record r{"lammps", "mpi x" + std::to_string(o.lammpsRanks), "fp64", "neighbour_list", n, t->steps, t->secondsPerStep};
                records.push_back(r);
                std::fprintf(stderr, "[corebox] md LAMMPS (%d MPI ranks) N = %lld: %.3f ms/step, %.4g particle-steps/s\n", o.lammpsRanks,
                             (long long)n, 1e3 * r.secondsPerStep, r.particleStepsPerSecond());
            }
        }
    }

    const HardwareInfo host = hostHardware();
    nlohmann::json json;
    json["benchmark"] = "md";
    json["command"] = o.commandLine;
    json["timestamp"] = utcTimestamp();
    json["backend"] = o.backend;
    json["device"] = device;
    json["host"] = hostJson(host);
    json["load_average_before"] = loadBefore;  // 1, 5 and 15 minutes
    json["load_average_after"] = loadAverage();
    const char* wait = std::getenv("OMP_WAIT_POLICY");
    json["omp_wait_policy"] = wait ? wait : "";
    json["lammps"] = lmp.empty() ? "" : lammpsVersion + " (" + lmp + ", " + std::to_string(o.lammpsRanks) + " MPI ranks)";
    char model[512];
    std::snprintf(model, sizeof model,
                  "Lennard-Jones fluid, number density %g, T = %g from a lattice, r_c = %g (no shift, LAMMPS lj/cut), skin 0.3, "
                  "velocity Verlet dt = %g, elastic walls (LAMMPS fix wall/reflect at a and L - a), no thermostat",
                  kMd.density, kMd.temperature, kMd.cutoff, kMd.dt);
    json["model"] = model;
    std::string csv = "code,backend,device,precision,forces,n,steps,ms_per_step,steps_per_second,particle_steps_per_second,"
                      "list_builds_per_step,force_passes_per_step,ms_forces,ms_collide\n";
    for (const Record& r : records) {
        const std::string where = r.code == "lammps" ? host.cpuModel : device;
        json["results"].push_back({{"code", r.code}, {"backend", r.backend}, {"precision", r.precision}, {"forces", r.forces}, {"n", r.n},
                                   {"steps", r.steps}, {"ms_per_step", 1e3 * r.secondsPerStep}, {"steps_per_second", r.stepsPerSecond()},
                                   {"particle_steps_per_second", r.particleStepsPerSecond()},
                                   {"list_builds_per_step", r.listBuildsPerStep}, {"force_passes_per_step", r.forcePassesPerStep},
                                   {"ms_forces", r.msForces}, {"ms_collide", r.msCollide}});
        csv += r.code + "," + r.backend + "," + csvQuote(where) + "," + r.precision + "," + r.forces + "," + std::to_string(r.n) + "," +
               std::to_string(r.steps) + "," + number(1e3 * r.secondsPerStep) + "," + number(r.stepsPerSecond()) + "," +
               number(r.particleStepsPerSecond()) + "," + number(r.listBuildsPerStep) + "," + number(r.forcePassesPerStep) + "," +
               number(r.msForces) + "," + number(r.msCollide) + "\n";
    }
    std::cout << csv;
    if (o.outputPrefix.empty()) return;
    writeResultFiles(o.outputPrefix,
                     "# " + o.commandLine + "\n# load average before " + loadBefore + ", after " + loadAverage() + "\n" + csv, json);
}

}  // namespace corebox
