// `corebox bench table1`: the report's Table 1 on this host's GPUs. Milliseconds per RK4 step with
// pair forces and hard-core collisions, N = 1024 ... 65536 (and, asked for, 262144 and 10^6), for every
// GPU count P and every exchange method (DT-S, DT-A, DA, NCCL), with speed-up and parallel efficiency
// against one GPU, pair interactions per second, and the report's own figures (report_table1.h) in the
// same rows. Writes PREFIX.csv (one row per configuration) and PREFIX.json, with the GPUs, driver, link
// topology and the command.
//
// Design note. Each configuration is a fresh Simulation on makeBackend(BackendChoice{"cuda", precision,
// 0, 0, P, exchange, N}), built exactly as `corebox run` builds one, so the time is that of a user's
// step (integrate, collide, health check), not of a kernel alone. The scene is the report's model at a
// fixed density the report does not state: bench_scenes.h's throughputScene at number density 0.5
// (one LJ species, hard cores of radius 0.56, T = 1.5, dt = 1e-3, no thermostat), the scene of
// `bench throughput`. `warmup` steps run first (allocations, first launches, NCCL connections); the
// last of them sets the steps per batch, so that a batch lasts about `batchSeconds`; each batch ends
// with backend finish() and is timed by the host clock; the figure is the median over `batches`.
// P = 1 runs once (no exchange) and is the baseline of the speed-ups. A configuration that fails (DA
// refused without peer access, a device error, an instability) is a row with its outcome and message,
// and the benchmark goes on. No GPU at all, or a P beyond the GPUs present, is a DeviceError (exit 4).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "vocabulary.h"

namespace corebox {

struct Table1Options {
    std::vector<int64_t> sizes{1024, 2048, 4096, 8192, 16384, 32768, 65536};  // the report's N
    std::vector<int> gpusList;  // P values; empty: 1 .. every GPU CUDA sees
    std::vector<Exchange> exchanges{Exchange::Dts, Exchange::Dta, Exchange::Da, Exchange::Nccl};
    std::vector<Precision> precisions{Precision::Fp32};
    int warmup = 3;             // untimed steps per configuration
    int batches = 5;            // timed batches; the median is the figure
    double batchSeconds = 0.2;  // aimed length of one batch [s]
    int maxBatchSteps = 1000;   // steps per batch at most (small N)
    std::string outputPrefix;   // writes PREFIX.csv and PREFIX.json; "": CSV on stdout only
    std::string commandLine;
};

struct Table1Result {
    int64_t n = 0;
    std::string precision;  // fp32 | fp64
    std::string method;     // the integrator: rk4
    int gpus = 0;           // P
    std::string exchange;   // dts | dta | da | nccl; "none" for P = 1
    std::string device;     // the backend's deviceName()
    std::string outcome;    // ok | device_error | instability | error
    std::string message;
    int batches = 0;  // timed batches done
    int stepsPerBatch = 0;
    double msPerStep = 0;  // median over the batches
    double msMin = 0, msMax = 0;
    double collisionsPerStep = 0;
    double roundsPerStep = 0;  // impact rounds of the collision stage
    // Where a timed step's time went, on the home GPU's stream (StepReport, mean over the timed steps):
    // the force passes (with several GPUs: from the home GPU's start to its last combine, the waits for
    // the others included), the rest of the integration (stages, exchanges), the collision stage.
    double msForces = 0, msIntegrate = 0, msCollide = 0;
    std::optional<double> speedup;         // ms(P = 1) / ms, same N and precision
    std::optional<double> efficiency;      // speed-up / P
    double pairInteractionsPerSecond = 0;  // 4 N^2 per RK4 step (N^2 per force pass) / time
};

std::vector<Table1Result> runTable1Benchmark(const Table1Options& options);

}  // namespace corebox
