// Parallel loops for the CPU backend. Reductions are deterministic: the index range is cut into
// chunks whose size does not depend on the thread count, each chunk is summed in order, and the
// chunk sums are added in chunk order.
#pragma once

#include <cstdint>
#include <vector>

namespace corebox {

constexpr int64_t kReductionChunk = 1024;
// Below this many items a loop runs on the calling thread: waking a thread team costs more than
// the work of a few hundred particles.
constexpr int64_t kParallelThreshold = 256;

template <class Fn>
void parallelFor(int threads, int64_t n, Fn&& fn) {
#pragma omp parallel for schedule(static) num_threads(threads) if (n >= kParallelThreshold)
    for (int64_t i = 0; i < n; ++i) fn(i);
}

// Same as parallelFor but with chunks handed out dynamically: for loops whose cost per index varies.
template <class Fn>
void parallelForDynamic(int threads, int64_t n, Fn&& fn) {
#pragma omp parallel for schedule(dynamic, 16) num_threads(threads) if (n >= kParallelThreshold)
    for (int64_t i = 0; i < n; ++i) fn(i);
}

// Sum of T over [0, n): value(i) -> T, T supporting += and value-initialisation.
template <class T, class Fn>
T deterministicSum(int threads, int64_t n, Fn&& value) {
    const int64_t chunks = (n + kReductionChunk - 1) / kReductionChunk;
    std::vector<T> partial(size_t(chunks), T{});
#pragma omp parallel for schedule(static) num_threads(threads) if (chunks > 1)
    for (int64_t c = 0; c < chunks; ++c) {
        T sum{};
        const int64_t end = (c + 1) * kReductionChunk < n ? (c + 1) * kReductionChunk : n;
        for (int64_t i = c * kReductionChunk; i < end; ++i) sum += value(i);
        partial[size_t(c)] = sum;
    }
    T total{};
    for (const T& p : partial) total += p;
    return total;
}

}  // namespace corebox
