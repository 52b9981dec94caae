// Force-pass benchmark: pair interactions per second of the all-pairs LJ force pass (the report's
// model: one species, no cutoff) on a backend, for a range of N and both precisions. Results go to
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
    std::string outputPrefix;  // writes PREFIX.csv and PREFIX.json; "" prints CSV only
    std::string commandLine;
};

struct ForceBenchmarkResult {
    Precision precision;
    int64_t n;
    int64_t passes;
    double seconds;
    double pairsPerSecond;
};

std::vector<ForceBenchmarkResult> runForceBenchmark(const ForceBenchmarkOptions& options);

}  // namespace corebox
