// `corebox bench throughput`: the performance record of a backend (DESIGN.md sec. 6). Force-pass
// pair interactions per second over N; ms per full step (integrate + collide) for every method and
// precision, with the collisions that step resolved; and, for the CUDA backend, interop and headless
// frame timings at a large N. Writes PREFIX.csv (one row per measurement) and PREFIX.json.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "scene.h"

namespace corebox {

struct ThroughputOptions {
    std::string backend = "cuda";
    std::vector<int64_t> forceSizes{1024, 4096, 16384, 65536, 262144, 1048576};
    int64_t stepN = 65536;
    std::vector<Method> methods{Method::Euler, Method::Rk2, Method::Rk4, Method::Dp5, Method::Hairer10, Method::Verlet};
    std::vector<Precision> precisions{Precision::Fp32, Precision::Fp64};
    int64_t frameN = 1000000;  // 0: no frame measurements
    int frameWidth = 1920, frameHeight = 1080;
    double minSeconds = 1.0;
    std::string outputPrefix;
    std::string commandLine;
};

void runThroughputBenchmark(const ThroughputOptions& options);

}  // namespace corebox
