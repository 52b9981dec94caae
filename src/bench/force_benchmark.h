// Force-pass benchmark: pair interactions per second of the all-pairs LJ force pass (the report's
// model: one species, no cutoff) on a backend, for a range of N and both precisions. Pair
// interactions are counted as NVIDIA's nbody sample counts them (N^2 a pass, here N (N - 1)), whatever
// the kernel does; the evaluations it actually did are reported beside them (half as many where each
// pair is evaluated once, with Newton's third law). On CUDA both kernels can be run: the pairs-once
// one (used where it pays) and the ordered one, on one GPU or several sharing the pass. Results go to
// CSV and JSON with the hardware and the command that produced them.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "backend_factory.h"

namespace corebox {

struct ForceBenchmarkOptions {
    std::string backend = "cpu";
    int threads = 0;
    std::vector<int64_t> sizes{1024, 4096, 16384};
    std::vector<Precision> precisions{Precision::Fp32, Precision::Fp64};
    double minSeconds = 1.0;  // repeat each measurement at least this long
    // CUDA: which all-pairs kernels to measure: true = each pair once where it applies, false = ordered pairs.
    std::vector<bool> pairsOnce{true, false};
    // CUDA: GPU counts P sharing the pass (the default exchange); the CPU runs once, as P = 1.
    std::vector<int> gpus{1};
    std::string outputPrefix;  // writes PREFIX.csv and PREFIX.json; "" prints CSV only
    std::string commandLine;
};

struct ForceBenchmarkResult {
    Precision precision;
    int64_t n;
    int gpus;
    std::string device;  // the backend's description (GPU count and exchange)
    std::string kernel;  // "pairs_once" or "ordered": what the passes ran
    int64_t passes;
    double seconds;
    double pairsPerSecond;        // N (N - 1) a pass
    double evaluationsPerSecond;  // pair evaluations the kernel did
};

std::vector<ForceBenchmarkResult> runForceBenchmark(const ForceBenchmarkOptions& options);

}  // namespace corebox
