#include "table1_benchmark.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "atomic_file.h"
#include "backend_factory.h"
#include "bench_scenes.h"
#include "errors.h"
#include "gpu_records.h"
#include "hardware_info.h"
#include "initial_conditions.h"
#include "report_table1.h"
#include "simulation.h"
#if COREBOX_WITH_CUDA
#include "nccl_environment.h"
#endif

namespace corebox {
namespace {

using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

// The report does not state its density (sec. 7: "presented for one fixed density"); this is ours.
constexpr double kDensity = 0.5;
constexpr Method kMethod = Method::Rk4;  // the report's integrator for Table 1
constexpr int kForcePassesPerStep = 4;   // RK4: one force pass per stage

const char* kModel =
    "the report's model at a density it does not state: one Lennard-Jones species (sigma = epsilon = m = 1), all "
    "pairs, hard cores of radius 0.56 colliding elastically (restitution 1) with each other and the walls, number "
    "density 0.5 in a cubic box of side (N / 0.5)^(1/3), lattice placement, T = 1.5 at start, no thermostat, RK4, "
    "dt = 1e-3 (bench_scenes.h: throughputScene, the scene of bench throughput)";
const char* kTiming =
    "per configuration: a fresh Simulation on makeBackend({cuda, precision, gpus P, exchange, N}) as corebox run "
    "builds it; warm-up steps, then batches of steps each ended by backend finish() and timed by the host clock "
    "(steady_clock); ms per step = median over the batches; pair interactions per second = 4 N^2 per RK4 step / "
    "time; speed-up = ms(P = 1) / ms(P), efficiency = speed-up / P; ms_forces, ms_integrate, ms_collide: the "
    "step's phases on the home GPU's stream (GPU events, StepReport), mean over the timed steps; where the RK step "
    "runs as one CUDA graph (one GPU, all pairs: src/cuda/cuda_rk_graph.cpp), ms_forces brackets the whole graph, "
    "the stage updates included";
const char* kReportNote =
    "report_*_ms: the report's Table 1 (CSTN-139 sec. 7), ms per RK4 step on 4 x Tesla C2070, same N; its "
    "density, temperature, time step and precision are not stated";

constexpr const char* kCsvHeader =
    "n,precision,method,gpus,exchange,outcome,ms_per_step,ms_min,ms_max,batches,steps_per_batch,speedup,efficiency,"
    "pair_interactions_per_second,collisions_per_step,rounds_per_step,ms_forces,ms_integrate,ms_collide,report_dts_ms,report_dta_ms,report_da_ms,device,message\n";

std::string optionalNumber(const std::optional<double>& value) { return value ? number(*value) : ""; }

std::string configName(const Table1Result& r) {
    char text[160];
    std::snprintf(text, sizeof text, "N = %lld %s P = %d %s", (long long)r.n, r.precision.c_str(), r.gpus,
                  r.exchange.c_str());
    return text;
}

// One configuration, start to end. Errors are caught and recorded: the benchmark goes on.
Table1Result measure(const Table1Options& o, Precision precision, int64_t n, int gpus, Exchange exchange) {
    Table1Result r;
    r.n = n;
    r.precision = precisionName(precision);
    r.method = methodName(kMethod);
    r.gpus = gpus;
    r.exchange = gpus == 1 ? "none" : exchangeName(exchange);
    try {
        const Scene scene = throughputScene(n, kDensity, precision, kMethod);
        BackendChoice choice;
        choice.name = "cuda";
        choice.precision = precision;
        choice.gpus = gpus;
        choice.exchange = gpus == 1 ? Exchange::Auto : exchange;
        choice.particleCount = n;
        SimulationLimits limits;
        limits.maxEnergyDrift = 1e9;  // timing only: an energy drift must not stop the measurement
        Simulation sim(scene, makeBackend(choice), makeInitialState(scene), limits);
        r.device = sim.backend().deviceName();

        double lastWarmup = 0;
        for (int k = 0; k < std::max(o.warmup, 1); ++k) {
            const Clock::time_point start = Clock::now();
            sim.step();
            sim.backend().finish();
            lastWarmup = secondsSince(start);
        }
        r.stepsPerBatch = int(
            std::clamp<double>(std::ceil(o.batchSeconds / std::max(lastWarmup, 1e-6)), 1.0, double(o.maxBatchSteps)));

        std::vector<double> msPerStep;
        int64_t collisions = 0, steps = 0, rounds = 0;
        double secondsForces = 0, secondsIntegrate = 0, secondsCollide = 0;
        Clock::time_point lastProgress = Clock::now();
        for (int b = 0; b < o.batches; ++b) {
            const Clock::time_point start = Clock::now();
            for (int s = 0; s < r.stepsPerBatch; ++s) {
                const StepReport report = sim.step();
                collisions += report.pairCollisions + report.wallCollisions;
                rounds += report.rounds;
                secondsForces += report.secondsForces;
                secondsIntegrate += report.secondsIntegrate;
                secondsCollide += report.secondsCollide;
            }
            sim.backend().finish();
            msPerStep.push_back(1e3 * secondsSince(start) / r.stepsPerBatch);
            steps += r.stepsPerBatch;
            if (secondsSince(lastProgress) > 2.0) {
                lastProgress = Clock::now();
                std::fprintf(stderr, "[corebox] bench table1: %s: batch %d of %d, %.3f ms/step\n",
                             configName(r).c_str(), b + 1, o.batches, msPerStep.back());
            }
        }
        r.batches = int(msPerStep.size());
        r.msPerStep = median(msPerStep);
        r.msMin = *std::min_element(msPerStep.begin(), msPerStep.end());
        r.msMax = *std::max_element(msPerStep.begin(), msPerStep.end());
        r.collisionsPerStep = double(collisions) / double(steps);
        r.roundsPerStep = double(rounds) / double(steps);
        r.msForces = 1e3 * secondsForces / double(steps);
        r.msIntegrate = 1e3 * secondsIntegrate / double(steps);
        r.msCollide = 1e3 * secondsCollide / double(steps);
        r.pairInteractionsPerSecond = kForcePassesPerStep * double(n) * double(n) / (1e-3 * r.msPerStep);
        r.outcome = "ok";
    } catch (const DeviceError& e) {
        r.outcome = "device_error";
        r.message = e.what();
    } catch (const InstabilityError& e) {
        r.outcome = "instability";
        r.message = e.what();
    } catch (const std::exception& e) {
        r.outcome = "error";
        r.message = e.what();
    }
    return r;
}

void addSpeedups(std::vector<Table1Result>& results) {
    for (Table1Result& r : results) {
        if (r.outcome != "ok") continue;
        for (const Table1Result& base : results) {
            if (base.gpus == 1 && base.outcome == "ok" && base.n == r.n && base.precision == r.precision) {
                r.speedup = base.msPerStep / r.msPerStep;
                r.efficiency = *r.speedup / r.gpus;
            }
        }
    }
}

void logResult(const Table1Result& r) {
    if (r.outcome != "ok") {
        std::fprintf(stderr, "[corebox] bench table1: %s: %s: %s\n", configName(r).c_str(), r.outcome.c_str(),
                     r.message.c_str());
        return;
    }
    std::fprintf(stderr,
                 "[corebox] bench table1: %s: %.3f ms/step (%d x %d steps; forces %.3f, integrate %.3f, collide %.3f), "
                 "%.3e pair interactions/s",
                 configName(r).c_str(), r.msPerStep, r.batches, r.stepsPerBatch, r.msForces, r.msIntegrate, r.msCollide,
                 r.pairInteractionsPerSecond);
    if (r.speedup && r.gpus > 1) std::fprintf(stderr, ", speed-up %.2f, efficiency %.2f", *r.speedup, *r.efficiency);
    const std::optional<ReportTable1Row> report = reportTable1Row(r.n);
    if (report)
        std::fprintf(stderr, " (report, 4 x C2070: %.2f ms)",
                     r.exchange == "dts"  ? report->dtsMs
                     : r.exchange == "da" ? report->daMs
                                          : report->dtaMs);
    std::fprintf(stderr, "\n");
}

std::string csvRow(const Table1Result& r) {
    const bool ok = r.outcome == "ok";
    const std::optional<ReportTable1Row> report = reportTable1Row(r.n);
    return std::to_string(r.n) + "," + r.precision + "," + r.method + "," + std::to_string(r.gpus) + "," + r.exchange +
           "," + r.outcome + "," + (ok ? number(r.msPerStep) : "") + "," + (ok ? number(r.msMin) : "") + "," +
           (ok ? number(r.msMax) : "") + "," + std::to_string(r.batches) + "," + std::to_string(r.stepsPerBatch) + "," +
           optionalNumber(r.speedup) + "," + optionalNumber(r.efficiency) + "," +
           (ok ? number(r.pairInteractionsPerSecond) : "") + "," + (ok ? number(r.collisionsPerStep) : "") + "," +
           (ok ? number(r.roundsPerStep) : "") + "," + (ok ? number(r.msForces) : "") + "," +
           (ok ? number(r.msIntegrate) : "") + "," + (ok ? number(r.msCollide) : "") + "," +
           (report ? number(report->dtsMs) : "") + "," + (report ? number(report->dtaMs) : "") + "," +
           (report ? number(report->daMs) : "") + "," + csvQuote(r.device) + "," + csvQuote(r.message) + "\n";
}

nlohmann::json resultJson(const Table1Result& r) {
    const bool ok = r.outcome == "ok";
    auto orNull = [](bool present, double v) { return present ? nlohmann::json(v) : nlohmann::json(nullptr); };
    const std::optional<ReportTable1Row> report = reportTable1Row(r.n);
    return {{"n", r.n},
            {"precision", r.precision},
            {"method", r.method},
            {"gpus", r.gpus},
            {"exchange", r.exchange},
            {"device", r.device},
            {"outcome", r.outcome},
            {"message", r.message},
            {"batches", r.batches},
            {"steps_per_batch", r.stepsPerBatch},
            {"ms_per_step", orNull(ok, r.msPerStep)},
            {"ms_min", orNull(ok, r.msMin)},
            {"ms_max", orNull(ok, r.msMax)},
            {"speedup", orNull(bool(r.speedup), r.speedup.value_or(0))},
            {"efficiency", orNull(bool(r.efficiency), r.efficiency.value_or(0))},
            {"pair_interactions_per_second", orNull(ok, r.pairInteractionsPerSecond)},
            {"collisions_per_step", orNull(ok, r.collisionsPerStep)},
            {"rounds_per_step", orNull(ok, r.roundsPerStep)},
            {"ms_forces", orNull(ok, r.msForces)},
            {"ms_integrate", orNull(ok, r.msIntegrate)},
            {"ms_collide", orNull(ok, r.msCollide)},
            {"report_dts_ms", orNull(bool(report), report ? report->dtsMs : 0)},
            {"report_dta_ms", orNull(bool(report), report ? report->dtaMs : 0)},
            {"report_da_ms", orNull(bool(report), report ? report->daMs : 0)}};
}

nlohmann::json reportJson() {
    nlohmann::json rows = nlohmann::json::array();
    for (const ReportTable1Row& row : kReportTable1)
        rows.push_back({{"n", row.n}, {"dts_ms", row.dtsMs}, {"dta_ms", row.dtaMs}, {"da_ms", row.daMs}});
    return {{"source", "Playne & Hawick 2012, CSTN-139, sec. 7, Table 1"},
            {"hardware", kReportTable1Hardware},
            {"gpus", kReportTable1Gpus},
            {"method", "rk4"},
            {"note",
             "ms per time step with potentials and hard-sphere collisions, one fixed density (not stated), accurate to "
             "+/-0.005 ms; density, temperature, time step and precision not stated"},
            {"rows", rows}};
}

void checkOptions(const Table1Options& o) {
    if (o.sizes.empty()) throw InputError("--sizes: at least one particle count");
    for (int64_t n : o.sizes) {
        if (n < 2) throw InputError("--sizes: particle counts must be >= 2, not " + std::to_string(n));
    }
    for (int p : o.gpusList) {
        if (p < 1) throw InputError("--gpus-list: GPU counts must be >= 1, not " + std::to_string(p));
    }
    for (Exchange e : o.exchanges) {
        if (e == Exchange::Auto) throw InputError("--exchanges: name the methods (dts, dta, da, nccl), not 'auto'");
    }
    if (o.exchanges.empty()) throw InputError("--exchanges: at least one method");
    if (o.precisions.empty()) throw InputError("--precision: at least one precision");
    if (o.warmup < 1) throw InputError("--warmup: at least 1 step (it sets the batch length)");
    if (o.batches < 1) throw InputError("--batches: must be >= 1");
    if (!(o.batchSeconds > 0)) throw InputError("--batch-seconds: must be > 0");
    if (o.maxBatchSteps < 1) throw InputError("--max-batch-steps: must be >= 1");
}

}  // namespace

std::vector<Table1Result> runTable1Benchmark(const Table1Options& options) {
    checkOptions(options);
    const GpuHardware gpus = gpuHardware();
#if COREBOX_WITH_CUDA
    // The NCCL exchange's backends make their communicators in this process: NVLink SHARP stays off
    // whether or not the backend prepares the environment itself (nccl_environment.h says why).
    prepareNcclEnvironment();
#else
    throw DeviceError(
        "bench table1 needs a CUDA device; this build of corebox has no CUDA backend (built without nvcc)");
#endif
    if (gpus.count == 0) throw DeviceError("bench table1 needs a CUDA device; found none (no NVIDIA driver or no GPU)");
    std::vector<int> gpusList = options.gpusList;
    if (gpusList.empty()) {
        for (int p = 1; p <= gpus.count; ++p) gpusList.push_back(p);
    }
    for (int p : gpusList) {
        if (p > gpus.count) {
            throw DeviceError("--gpus-list " + std::to_string(p) + ": only " + std::to_string(gpus.count) +
                              " CUDA device" + (gpus.count == 1 ? "" : "s") + " found");
        }
    }
    std::sort(gpusList.begin(), gpusList.end());
    gpusList.erase(std::unique(gpusList.begin(), gpusList.end()), gpusList.end());
    if (!options.outputPrefix.empty()) {
        AtomicFile probe(options.outputPrefix + ".json");  // an unwritable --out fails now, not after the runs
    }

    std::vector<Table1Result> results;
    for (Precision precision : options.precisions) {
        for (int64_t n : options.sizes) {
            for (int p : gpusList) {
                // One GPU exchanges nothing: one run, the baseline of every method's speed-up.
                const std::vector<Exchange> exchanges =
                    p == 1 ? std::vector<Exchange>{Exchange::Auto} : options.exchanges;
                for (Exchange e : exchanges) {
                    results.push_back(measure(options, precision, n, p, e));
                    addSpeedups(results);
                    logResult(results.back());
                }
            }
        }
    }

    std::string table = kCsvHeader;
    for (const Table1Result& r : results) table += csvRow(r);
    std::cout << table;
    if (options.outputPrefix.empty()) return results;
    const std::string notes = std::string("bench table1: ") + kModel + "\n" + kTiming + "\n" + kReportNote;
    nlohmann::json json;
    json["benchmark"] = "table1";
    json["command"] = options.commandLine;
    json["timestamp"] = utcTimestamp();
    json["host"] = hostJson(hostHardware());
    json["gpu"] = gpuHardwareJson(gpus);
    json["device"] = gpus.devices.front();
    json["model"] = kModel;
    json["density"] = kDensity;
    json["timing"] = kTiming;
    json["warmup"] = options.warmup;
    json["batches"] = options.batches;
    json["batch_seconds"] = options.batchSeconds;
    json["report"] = reportJson();
    json["results"] = nlohmann::json::array();
    for (const Table1Result& r : results) json["results"].push_back(resultJson(r));
    writeResultFiles(options.outputPrefix, gpuCsvPreamble(options.commandLine, gpus, notes) + table, json);
    return results;
}

}  // namespace corebox
