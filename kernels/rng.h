// Counter-based random numbers: Philox4x32-10 (Salmon et al., "Parallel random numbers: as easy
// as 1, 2, 3", SC'11). A draw is a pure function of (seed, particle id, step, purpose), so the CPU
// backend, one GPU and many GPUs produce the same numbers regardless of how work is scheduled.
#pragma once

#include <cmath>
#include <cstdint>

#include "hd.h"

namespace corebox {

struct Philox4 {
    uint32_t v[4];
};

COREBOX_HD inline void philoxMulHiLo(uint32_t a, uint32_t b, uint32_t* hi, uint32_t* lo) {
    const uint64_t p = uint64_t(a) * uint64_t(b);
    *hi = uint32_t(p >> 32);
    *lo = uint32_t(p);
}

COREBOX_HD inline Philox4 philox4x32(uint64_t seed, uint32_t c0, uint32_t c1, uint32_t c2, uint32_t c3) {
    uint32_t k0 = uint32_t(seed), k1 = uint32_t(seed >> 32);
    uint32_t x0 = c0, x1 = c1, x2 = c2, x3 = c3;
    for (int round = 0; round < 10; ++round) {
        uint32_t hi0, lo0, hi1, lo1;
        philoxMulHiLo(0xD2511F53u, x0, &hi0, &lo0);
        philoxMulHiLo(0xCD9E8D57u, x2, &hi1, &lo1);
        const uint32_t y0 = hi1 ^ x1 ^ k0, y1 = lo1, y2 = hi0 ^ x3 ^ k1, y3 = lo0;
        x0 = y0; x1 = y1; x2 = y2; x3 = y3;
        k0 += 0x9E3779B9u;
        k1 += 0xBB67AE85u;
    }
    return {{x0, x1, x2, x3}};
}

// What a draw is for; part of the counter so different uses never share numbers.
enum class RngPurpose : uint32_t { InitialVelocity = 1, Placement = 2, Thermostat = 3, LatticeShuffle = 4 };

// Uniform in (0, 1), 53 random bits, never exactly 0 or 1.
COREBOX_HD inline double uniformOpen(uint32_t hi, uint32_t lo) {
    const uint64_t bits = (uint64_t(hi) << 21) ^ uint64_t(lo >> 11);  // 53 bits
    return (double(bits & ((uint64_t(1) << 53) - 1)) + 0.5) * (1.0 / 9007199254740992.0);
}

// Two independent standard normals from one Philox block (Box-Muller).
COREBOX_HD inline void gaussianPair(const Philox4& r, double* g0, double* g1) {
    const double u1 = uniformOpen(r.v[0], r.v[1]);
    const double u2 = uniformOpen(r.v[2], r.v[3]);
    const double radius = sqrt(-2.0 * log(u1));
    const double angle = 6.283185307179586476925286766559 * u2;
    *g0 = radius * cos(angle);
    *g1 = radius * sin(angle);
}

// Counter layout shared by every user: c0 = id, c1/c2 = 64-bit step or index, c3 = purpose.
COREBOX_HD inline Philox4 drawBlock(uint64_t seed, uint32_t id, uint64_t counter, RngPurpose purpose) {
    return philox4x32(seed, id, uint32_t(counter), uint32_t(counter >> 32), uint32_t(purpose));
}

}  // namespace corebox
