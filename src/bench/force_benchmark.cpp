#include "force_benchmark.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>

#include "atomic_file.h"
#include "bench_scenes.h"
#include "force_pass.h"
#include "hardware_info.h"
#include "initial_conditions.h"

namespace corebox {
namespace {

void writeResults(const ForceBenchmarkOptions& options, const std::vector<ForceBenchmarkResult>& results,
                  const std::string& deviceName) {
    const HardwareInfo host = hostHardware();
    std::string csv = "backend,device,threads,gpus,precision,n,kernel,passes,seconds,pair_interactions_per_second,"
                      "pair_evaluations_per_second,pair_interactions_per_second_per_gpu\n";
    nlohmann::json json;
    json["benchmark"] = "force_pass";
    json["command"] = options.commandLine;
    json["timestamp"] = utcTimestamp();
    json["backend"] = options.backend;
    json["device"] = deviceName;
    json["host"] = {{"cpu", host.cpuModel}, {"hardware_threads", host.hardwareThreads}};
    json["model"] = "Lennard-Jones, one species, all pairs (no cutoff), number density 0.5";
    for (const ForceBenchmarkResult& r : results) {
        char line[512];
        std::snprintf(line, sizeof line, "%s,\"%s\",%d,%d,%s,%lld,%s,%lld,%.6f,%.6e,%.6e,%.6e\n", options.backend.c_str(),
                      r.device.c_str(), options.threads > 0 ? options.threads : host.hardwareThreads, r.gpus, precisionName(r.precision),
                      (long long)r.n, r.kernel.c_str(), (long long)r.passes, r.seconds, r.pairsPerSecond, r.evaluationsPerSecond,
                      r.pairsPerSecond / r.gpus);
        csv += line;
        json["results"].push_back({{"precision", precisionName(r.precision)},
                                   {"n", r.n},
                                   {"gpus", r.gpus},
                                   {"device", r.device},
                                   {"kernel", r.kernel},
                                   {"passes", r.passes},
                                   {"seconds", r.seconds},
                                   {"pair_interactions_per_second", r.pairsPerSecond},
                                   {"pair_evaluations_per_second", r.evaluationsPerSecond},
                                   {"pair_interactions_per_second_per_gpu", r.pairsPerSecond / r.gpus}});
    }
    std::cout << csv;
    if (options.outputPrefix.empty()) return;
    AtomicFile csvFile(options.outputPrefix + ".csv");
    csvFile.stream() << "# " << options.commandLine << "\n" << csv;
    csvFile.commit();
    AtomicFile jsonFile(options.outputPrefix + ".json");
    jsonFile.stream() << json.dump(2) << "\n";
    jsonFile.commit();
    std::fprintf(stderr, "[corebox] wrote %s.csv and %s.json\n", options.outputPrefix.c_str(), options.outputPrefix.c_str());
}

}  // namespace

std::vector<ForceBenchmarkResult> runForceBenchmark(const ForceBenchmarkOptions& options) {
    std::vector<ForceBenchmarkResult> results;
    std::string deviceName;
    // The CPU has one all-pairs kernel (ordered pairs): one run per size.
    const bool oneKernel = options.backend == "cpu" || options.pairsOnce.empty();
    const std::vector<bool> kernels = oneKernel ? std::vector<bool>{true} : options.pairsOnce;
    const std::vector<int> gpuCounts = options.backend == "cpu" ? std::vector<int>{1} : options.gpus;
    for (Precision precision : options.precisions) {
        for (int64_t n : options.sizes) {
            for (int gpus : gpuCounts) {
                for (bool pairsOnce : kernels) {
                    const Scene scene = throughputScene(n, 0.5, precision, Method::Rk4);
                    BackendChoice choice{options.backend, precision, options.threads};
                    choice.gpus = gpus;
                    choice.pairsOnce = pairsOnce;
                    const std::unique_ptr<Backend> backend = forcePassBackend(choice, scene);
                    if (deviceName.empty()) deviceName = backend->deviceName();
                    // Warm-up (page in buffers, spin up threads); its evaluations tell which kernel runs.
                    const int64_t setUpEvaluations = backend->forceCounters().allPairsEvaluations;
                    const int64_t warmUpPairs = runForcePass(*backend, n);
                    const int64_t evaluations0 = backend->forceCounters().allPairsEvaluations;
                    const std::string kernel = evaluations0 - setUpEvaluations < warmUpPairs ? "pairs_once" : "ordered";
                    // pairs_once asked for where it does not apply runs the ordered kernel: measured once, as ordered.
                    if (!oneKernel && pairsOnce && kernel == "ordered" &&
                        std::find(kernels.begin(), kernels.end(), false) != kernels.end())
                        continue;
                    using Clock = std::chrono::steady_clock;
                    const Clock::time_point start = Clock::now();
                    int64_t passes = 0, pairs = 0;
                    double seconds = 0;
                    do {
                        pairs += runForcePass(*backend, n);
                        ++passes;
                        seconds = std::chrono::duration<double>(Clock::now() - start).count();
                    } while (seconds < options.minSeconds);
                    const int64_t evaluations = backend->forceCounters().allPairsEvaluations - evaluations0;
                    results.push_back({precision, n, gpus, backend->deviceName(), kernel, passes, seconds,
                                       double(pairs) / seconds, double(evaluations) / seconds});
                    std::fprintf(
                        stderr,
                        "[corebox] bench forces: %s N = %lld, P = %d, %s: %.3e pair interactions/s (%.3e a GPU), %.3e "
                        "evaluations/s (%lld passes, %.2f s)\n",
                        precisionName(precision), (long long)n, gpus, kernel.c_str(), double(pairs) / seconds,
                        double(pairs) / seconds / gpus, double(evaluations) / seconds, (long long)passes, seconds);
                }
            }
        }
    }
    writeResults(options, results, deviceName);
    return results;
}

}  // namespace corebox
