// `corebox bench p2p`: the report's Figure 5 on this host's GPUs. Transfer time against size, 4 KiB to
// 2 GiB in powers of two, for the report's three peer methods (DT-S, DT-A, DA) and an NCCL all-gather,
// with P GPUs each fetching its neighbour's buffer at the same time (src/cuda/peer_transfers.h says how
// each method is issued and timed). Writes PREFIX.csv (one row per method and size) and PREFIX.json,
// with the GPUs, driver, link topology, peer-access matrix and the command.
//
// Design note. A repeat is one transfer on every device, timed by the host clock from a full
// synchronisation to the completion of all of them; `warmup` repeats are dropped (first-touch costs,
// NCCL's connection set-up), and the median of `repeats` is the figure, with the fastest and slowest
// beside it. Bandwidth is the bytes each GPU received over that time (NCCL: the P - 1 other buffers).
// A method that cannot run (DA without peer access) or fails is a row with its message, not an exit:
// the other methods still run. Fewer than 2 GPUs is a DeviceError (exit code 4).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "vocabulary.h"

namespace corebox {

struct P2pBenchmarkOptions {
    int gpus = 0;                           // GPUs 0 .. P-1; 0: every GPU CUDA sees (at least 2)
    uint64_t minBytes = 4096;               // smallest transfer per GPU [bytes]
    uint64_t maxBytes = uint64_t(1) << 31;  // largest transfer per GPU [bytes] (2 GiB)
    int repeats = 50;                       // timed repeats per method and size (the median is kept)
    int warmup = 3;                         // untimed repeats before them
    std::vector<Exchange> methods{Exchange::Dts, Exchange::Dta, Exchange::Da, Exchange::Nccl};
    std::string outputPrefix;  // writes PREFIX.csv and PREFIX.json; "": CSV on stdout only
    std::string commandLine;
};

struct P2pResult {
    std::string method;  // dts | dta | da | nccl
    int gpus = 0;
    uint64_t bytes = 0;          // each GPU's buffer
    uint64_t bytesReceived = 0;  // per GPU: bytes (copies, DA); (P - 1) bytes (all-gather)
    int repeats = 0;             // timed repeats done
    double medianSeconds = 0;
    double minSeconds = 0;
    double maxSeconds = 0;
    double gbPerSecondPerGpu = 0;  // bytesReceived / median, 1e9 bytes per GB
    double gbPerSecondTotal = 0;   // P bytesReceived / median
    std::string path;       // peer | host (staged through host memory) | nccl (NCCL's own choice) | none (refused)
    bool verified = false;  // the neighbour's bytes were found where they belong
    std::string outcome;    // ok | refused | device_error | error
    std::string message;
};

std::vector<P2pResult> runP2pBenchmark(const P2pBenchmarkOptions& options);

}  // namespace corebox
