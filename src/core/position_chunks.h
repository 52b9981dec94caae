// Positions of another precision handed to a PositionSink (backend.h) as doubles, a chunk at a time, the
// chunks on several threads: a reader converts them into its own memory from a chunk still in cache,
// and no full-length array of doubles is written between. Included by the backends, which are built
// with OpenMP (without it, one thread). The CUDA backend gives it every core (threads 0), the CPU backend
// its own threads.
//
// Why: the World's mirror of 10^5 balls (an H200's host, 16 cores, fp32) took two full-length passes on
// one thread before, the conversion into a vector of doubles and its copy into the mirror: 0.77 to 0.92
// ms a landing frame of the sandbox example with the download; chunked on one thread 0.56, on every core
// 0.27 to 0.29 (host probes; the same positions).
#pragma once

#ifdef _OPENMP
#include <omp.h>
#endif

#include <algorithm>
#include <cstddef>
#include <cstdint>

#include "backend.h"

namespace corebox {

constexpr size_t kPositionChunk = 2048;  // 48 KiB of doubles

// threads: 0 for every core (omp_get_max_threads).
template <class Real>
void handInChunks(const Vec3<Real>* x, size_t count, const PositionSink& sink, int threads) {
    const int64_t chunks = int64_t((count + kPositionChunk - 1) / kPositionChunk);
#ifdef _OPENMP
    const int team = threads > 0 ? threads : omp_get_max_threads();
#pragma omp parallel for schedule(static) num_threads(team) if (chunks >= 4)
#else
    (void)threads;
#endif
    for (int64_t c = 0; c < chunks; ++c) {
        Vec3<double> chunk[kPositionChunk];
        const size_t first = size_t(c) * kPositionChunk;
        const size_t m = std::min(kPositionChunk, count - first);
        for (size_t k = 0; k < m; ++k) chunk[k] = vec3Cast<double>(x[first + k]);
        sink(first, chunk, m);
    }
}

}  // namespace corebox
