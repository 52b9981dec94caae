// What `corebox bench pile` measures of a ball pile, written once and used by both engines it compares:
// the benchmark (corebox's runs) and the Bullet driver (bullet_pile_driver.cpp), so that an overlap,
// an escape, a time to rest or a frame time means the same thing in both columns.
//
// Design note. Everything here works on plain host data (positions in double, energy samples, frame
// times), header-only, so the Bullet driver needs only corebox_core (the host cell list) and no
// backend. The definitions:
//  - overlap: the deepest pair overlap (2a - r) / 2a of the state, found with the one host cell list
//    (host_cell_list.h); wall penetration likewise (a - distance to the wall) / 2a;
//  - outside: centres beyond a wall plane (outside [0, L]), the rule of the backends' health check;
//  - time to rest: the first sample from which on the kinetic energy stays below `restFraction` of
//    the potential energy released so far (U(0) - U(t)); none when the last sample is not at rest;
//  - frame times: the mean over the run and over the last second of frames.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <optional>
#include <vector>

#include "host_cell_list.h"
#include "vec3.h"

namespace corebox {

struct PileStateMeasures {
    double maxOverlap = 0;          // deepest pair overlap as a fraction of the diameter
    double maxWallPenetration = 0;  // deepest wall penetration as a fraction of the diameter
    int64_t outside = 0;            // centres outside [0, L] on some axis (escaped)
    int64_t nonFinite = 0;          // positions that are not finite (left out of the other measures)
};

// Equal radii `radius` in a box [0, L] per axis.
inline PileStateMeasures measurePileState(const std::vector<Vec3<double>>& x, double radius,
                                          const std::array<double, 3>& box) {
    PileStateMeasures m;
    const double diameter = 2 * radius;
    std::vector<char> finite(x.size(), 1);
    for (size_t i = 0; i < x.size(); ++i) {
        bool out = false;
        for (int a = 0; a < 3; ++a) {
            const double p = x[i][a];
            if (!std::isfinite(p)) {
                finite[i] = 0;
                break;
            }
            out = out || p < 0 || p > box[size_t(a)];
            m.maxWallPenetration =
                std::max({m.maxWallPenetration, (radius - p) / diameter, (p - (box[size_t(a)] - radius)) / diameter});
        }
        if (!finite[i])
            ++m.nonFinite;
        else if (out)
            ++m.outside;
    }
    CellList grid;
    grid.build(x, Vec3<double>{box[0], box[1], box[2]}, diameter);
    for (size_t i = 0; i < x.size(); ++i) {
        if (!finite[i]) continue;
        grid.forNeighbours(x[i], [&](int64_t j) {
            if (j <= int64_t(i) || !finite[size_t(j)]) return;
            const double r = std::sqrt(norm2(x[i] - x[size_t(j)]));
            m.maxOverlap = std::max(m.maxOverlap, (diameter - r) / diameter);
        });
    }
    return m;
}

struct PileEnergySample {
    double time = 0;       // simulated [tau]
    double kinetic = 0;    // [eps]
    double potential = 0;  // gravitational, m g z with z = 0 on the floor [eps]
};

// Kinetic energy below this fraction of the potential energy released counts as rest.
constexpr double kPileRestFraction = 0.01;

inline std::optional<double> pileTimeToRest(const std::vector<PileEnergySample>& samples,
                                            double restFraction = kPileRestFraction) {
    if (samples.empty()) return std::nullopt;
    const double u0 = samples.front().potential;
    std::optional<double> rest;
    // Walk back from the end while the samples are at rest; the last one walked is the answer.
    for (size_t k = samples.size(); k-- > 0;) {
        const PileEnergySample& s = samples[k];
        const double released = u0 - s.potential;
        if (!(released > 0 && s.kinetic < restFraction * released)) break;
        rest = s.time;
    }
    return rest;
}

// Wall-clock milliseconds of each 1/60 s frame.
struct PileFrameTimes {
    std::vector<double> ms;

    double mean() const { return meanOfLast(ms.size()); }
    // The mean of the last `count` frames (all of them when there are fewer).
    double meanOfLast(size_t count) const {
        count = std::min(count, ms.size());
        if (count == 0) return 0;
        double sum = 0;
        for (size_t k = ms.size() - count; k < ms.size(); ++k) sum += ms[k];
        return sum / double(count);
    }
};

}  // namespace corebox
