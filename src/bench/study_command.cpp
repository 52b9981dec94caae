// `corebox study` on the command line: the progress line, the summary and the result files of the
// study (study.h).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>

#include <nlohmann/json.hpp>

#include "gpu_records.h"
#include "hardware_info.h"
#include "initial_conditions.h"
#include "scene_io.h"
#include "study.h"
#include "vocabulary.h"

namespace corebox {
namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

std::string csvOf(const StudyResult& r) {
    std::string csv = "kind,method,precision,dt,tolerance,state_error,energy_error_max,energy_drift_rate,force_passes_per_time,"
                      "wall_seconds_per_time,order,stable_dt,unstable_dt,outcome\n";
    for (const StudyRun& run : r.runs) {
        csv += std::string("run,") + methodName(run.method) + "," + precisionTable().name(run.precision) + "," + number(run.dt) + "," +
               number(run.tolerance) + "," + number(run.stateError) + "," + number(run.energyErrorMax) + "," +
               number(run.energyDriftRate) + "," + number(run.forcePassesPerTime) + "," + number(run.wallSecondsPerTime) + ",,,," +
               run.outcome + "\n";
    }
    for (Method m : r.methods) {
        for (Precision p : r.precisions) {
            csv += std::string("order,") + methodName(m) + "," + precisionTable().name(p) + ",,,,,,,," + number(observedOrder(r, m, p)) +
                   ",,,ok\n";
        }
    }
    for (const StabilityLimit& l : r.limits) {
        csv += std::string("stability,") + methodName(l.method) + "," + precisionTable().name(l.precision) + ",,,,,,,,," +
               number(l.stableDt) + "," + number(l.unstableDt) + "," + (l.failure.empty() ? "none" : l.failure) + "\n";
    }
    return csv;
}

nlohmann::json numberOrNull(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

nlohmann::json jsonOf(const StudyResult& r, const StudyOptions& o, const Scene& scene, double wallSeconds) {
    nlohmann::json j;
    j["benchmark"] = "study";
    j["wall_seconds"] = wallSeconds;  // the whole study, reference and stability included
    j["command"] = o.commandLine;
    j["timestamp"] = utcTimestamp();
    j["scene"] = o.scenePath;
    j["backend"] = o.backend;
    j["device"] = r.device;
    j["host"] = hostJson(hostHardware());
    j["particles"] = r.particles;
    j["scene_dt"] = scene.integrator.dt;
    j["horizon"] = r.horizon;
    j["long_run"] = r.longRun;
    j["thermostat"] = r.thermostat;
    j["reference"] = r.reference;
    j["reference_error"] = r.referenceError;
    for (const StudyRun& run : r.runs) {
        j["runs"].push_back({{"method", methodName(run.method)},
                             {"precision", precisionTable().name(run.precision)},
                             {"dt", run.dt},
                             {"tolerance", run.tolerance},
                             {"state_error", numberOrNull(run.stateError)},
                             {"energy_error_max", numberOrNull(run.energyErrorMax)},
                             {"energy_drift_rate", numberOrNull(run.energyDriftRate)},
                             {"force_passes_per_time", run.forcePassesPerTime},
                             {"wall_seconds_per_time", run.wallSecondsPerTime},
                             {"outcome", run.outcome},
                             {"message", run.message}});
    }
    for (Method m : r.methods) {
        for (Precision p : r.precisions) {
            j["orders"].push_back({{"method", methodName(m)}, {"precision", precisionTable().name(p)}, {"order", numberOrNull(observedOrder(r, m, p))}});
        }
    }
    for (const StabilityLimit& l : r.limits) {
        j["stability"].push_back({{"method", methodName(l.method)},
                                  {"precision", precisionTable().name(l.precision)},
                                  {"stable_dt", l.stableDt},
                                  {"unstable_dt", l.unstableDt},
                                  {"failure", l.failure.empty() ? "none" : l.failure}});
    }
    return j;
}

}  // namespace

void runStudyCommand(const StudyOptions& o) {
    const Scene scene = loadScene(o.scenePath);
    const Clock::time_point start = Clock::now();
    Clock::time_point lastPrint = Clock::now() - std::chrono::seconds(10);
    auto progress = [&](int done, int total, const std::string& what) {
        if (o.quiet) return;
        if (done < total && secondsSince(lastPrint) < 2.0) return;
        lastPrint = Clock::now();
        constexpr int kWidth = 30;
        const int filled = total > 0 ? kWidth * done / total : kWidth;
        std::fprintf(stderr, "[corebox] study [%s%s] %d/%d, %.0f s: %s\n", std::string(size_t(filled), '#').c_str(),
                     std::string(size_t(kWidth - filled), '.').c_str(), done, total, secondsSince(start), what.c_str());
    };
    const StudyResult r = runStudy(scene, makeInitialState(scene), o, progress);
    const std::string csv = csvOf(r);
    std::cout << csv;
    if (!o.quiet) {
        std::fprintf(stderr, "[corebox] study of %s: %lld particles on %s, T = %g, L = %g, reference %s (its own error %.3g sigma), %.0f s\n",
                     o.scenePath.c_str(), (long long)r.particles, r.device.c_str(), r.horizon, r.longRun, r.reference.c_str(),
                     r.referenceError, secondsSince(start));
    }
    if (o.outputPrefix.empty()) return;
    std::string preamble = "# " + o.commandLine + "\n";
    preamble += "# scene " + o.scenePath + ", " + std::to_string(r.particles) + " particles, " + r.device + ", thermostat " + r.thermostat + "\n";
    char line[256];
    std::snprintf(line, sizeof line, "# horizon T = %.6g, long run L = %.6g, reference %s, its error %.6g sigma\n", r.horizon, r.longRun,
                  r.reference.c_str(), r.referenceError);
    preamble += line;
    writeResultFiles(o.outputPrefix, preamble + csv, jsonOf(r, o, scene, secondsSince(start)));
}

}  // namespace corebox
