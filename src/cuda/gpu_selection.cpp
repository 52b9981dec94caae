// What `--gpus auto` and `--exchange auto` choose, from `corebox bench table1` on four and eight H200s
// with NVLink (docs/results/table1_h200x{4,8}*.csv, docs/multi_gpu.md; RK4 with collisions, fp32). A step
// costs about c N^2 / P for the force passes plus a part that does not shrink with P (the collision
// stage on the home GPU, the exchanges and the gather), so one GPU wins at small N and every GPU at
// large N.
#include <algorithm>

#include "cuda_backend.h"

namespace corebox {
namespace {

// Measured: two GPUs first beat one at N = 16384 (0.99 against 1.24 ms per step; at 8192 they tie;
// with the pairs-once pass shared by both, on two H200s, still there: 0.98 against 1.00 ms, then 1.35x at
// 32768; with the collision rounds on the device and the RK step a graph, 0.844 against 0.848 ms, then
// 1.41x at 32768, docs/results/table1_h200x2*.csv), and four first beat two at N = 32768 (1.52 against 2.07 ms;
// at 16384 they tie; measured before the pass was shared, as the eight-GPU figures). On eight GPUs the
// same rule holds: four are fastest at 32768 (1.63 against 1.69 ms on eight), eight at 65536 (3.00
// against 3.93 ms on four).
constexpr int64_t kFirstSplitN = 16384;

}  // namespace

int gpusFor(int64_t n, int visible) {
    if (visible <= 1 || n < kFirstSplitN) return 1;
    // One more GPU per 8192 particles: 2 at 16384, 4 at 32768, as measured.
    const int64_t useful = std::max<int64_t>(1, n / (kFirstSplitN / 2));
    return int(std::min<int64_t>(visible, useful));
}

Exchange fastestExchange(int gpus, bool peerAccess) {
    // Measured: the NCCL all-gather is the fastest at every N where several GPUs pay off, on two,
    // three and four GPUs (65536: 6.37, 4.77, 3.83 ms against 6.42, 4.94, 4.10 for DT-A); DA is
    // within 2 %, DT-S the slowest (its host waits). On eight, DA is 6 % faster at N = 65536 (3.00
    // against 3.19 ms), where the eight slices are small and NCCL's fixed cost per collective shows,
    // and within 1 % of NCCL at 262144 and 10^6. DA needs peer access between every pair.
    return gpus >= 8 && peerAccess ? Exchange::Da : Exchange::Nccl;
}

}  // namespace corebox
