// The host's element-wise conversions of the particle state it reads back and sends (the World's
// mirror, a backend's uploads and downloads, positions handed to a PositionSink): memory-bound loops on
// the thread that steps, while the GPU idles, so long ones run on several threads. Included by the
// backends and the World, which are built with OpenMP (without it, one thread).
//
// Why: at 10^5 balls on an H200's host (16 cores, fp32, the sandbox example, host probes) the World's
// positions() took two full-length passes on one thread, the conversion into a vector of doubles and its
// copy into the mirror: 0.77 to 0.92 ms a landing frame with the download; handed over in chunks on one
// thread 0.56, on every core 0.27 to 0.29 (the same positions). An edit read the state back in 2.3 to
// 2.6 ms and built the state it sends in 2.4 to 2.7, each a fresh array on one thread.
#pragma once

#ifdef _OPENMP
#include <omp.h>
#endif

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <type_traits>
#include <utility>

#include "backend.h"

namespace corebox {

// Below this many elements a conversion runs on the calling thread: waking a team costs more.
constexpr int64_t kParallelConversionFrom = 16384;

// fn(i) for i in [0, n), on `threads` threads (0: every core) where `parallel`, else on the caller's.
template <class Fn>
void loopOnThreads(int64_t n, int threads, bool parallel, Fn&& fn) {
#ifdef _OPENMP
    const int team = threads > 0 ? threads : omp_get_max_threads();
#pragma omp parallel for schedule(static) num_threads(team) if (parallel && team > 1)
#else
    (void)threads;
    (void)parallel;
#endif
    for (int64_t i = 0; i < n; ++i) fn(i);
}

// A conversion of n elements: on several threads where n is long enough.
template <class Fn>
void conversionLoop(int64_t n, int threads, Fn&& fn) {
    loopOnThreads(n, threads, n >= kParallelConversionFrom, std::forward<Fn>(fn));
}

constexpr size_t kPositionChunk = 2048;  // 48 KiB of doubles

// Positions handed to a PositionSink (Backend::readPositions). Doubles go as they are, at once; another
// precision as doubles a chunk at a time, the chunks on `threads` threads (0: every core): the sink
// converts them into its own memory from a chunk still in cache, and no full-length array of doubles is
// written between.
template <class Real>
void handPositions(const Vec3<Real>* x, size_t count, const PositionSink& sink, int threads) {
    if (count == 0) return;
    if constexpr (std::is_same<Real, double>::value) {
        (void)threads;
        sink(0, x, count);
    } else {
        const int64_t chunks = int64_t((count + kPositionChunk - 1) / kPositionChunk);
        loopOnThreads(chunks, threads, int64_t(count) >= kParallelConversionFrom, [&](int64_t c) {
            Vec3<double> chunk[kPositionChunk];
            const size_t first = size_t(c) * kPositionChunk;
            const size_t m = std::min(kPositionChunk, count - first);
            for (size_t k = 0; k < m; ++k) chunk[k] = vec3Cast<double>(x[first + k]);
            sink(first, chunk, m);
        });
    }
}

}  // namespace corebox
