// What `--gpus auto` and `--exchange auto` choose, from the measurements of `corebox bench table1`
// on H200s with NVLink (docs/table1.md). An all-pairs step costs about c N^2 / P for the force
// passes plus a fixed cost per step that grows with P (exchanges, events, the gather before the
// collision stage), so one GPU wins at small N and every GPU at large N.
#include <algorithm>

#include "cuda_backend.h"

namespace corebox {
namespace {

// Smallest N at which the measured step time with P GPUs (any exchange) beat P - 1 GPUs
// (docs/results/table1_h200x2.csv: P = 2 first wins at N = 16384).
constexpr int64_t kFirstSplitN = 16384;

}  // namespace

int gpusFor(int64_t n, int visible) {
    if (visible <= 1 || n < kFirstSplitN) return 1;
    // Each further GPU needs about as many particles again as the first split did.
    const int64_t useful = std::max<int64_t>(1, n / (kFirstSplitN / 2));
    return int(std::min<int64_t>(visible, useful));
}

Exchange fastestExchange(int gpus) {
    // docs/results/table1_h200x2.csv: DT-A is fastest or within noise of the fastest at every N on two
    // GPUs (no host waits, copies overlap the other device's work).
    (void)gpus;
    return Exchange::Dta;
}

}  // namespace corebox
