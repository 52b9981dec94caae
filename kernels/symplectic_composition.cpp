#include "symplectic_composition.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace corebox {
namespace {

// Velocity Verlet steps of relative lengths w_1 .. w_m in turn: kick w1/2, drift w1, kick (w1 + w2)/2,
// ..., drift w_m, kick w_m/2 (the two half kicks between steps merged: same accelerations).
SymplecticComposition verletSteps(const std::vector<double>& w, int order) {
    SymplecticComposition c;
    c.order = order;
    double pending = 0;
    for (double wi : w) {
        c.ops.push_back({CompositionOp::Kick, pending + 0.5 * wi});
        c.ops.push_back({CompositionOp::Drift, wi});
        pending = 0.5 * wi;
    }
    c.ops.push_back({CompositionOp::Kick, pending});
    return c;
}

// A symmetric composition from its outer half w_k .. w_1 and the middle w_0 = 1 - 2 sum w_i.
std::vector<double> symmetric(const std::vector<double>& outerToInner) {
    double sum = 0;
    for (double w : outerToInner) sum += w;
    std::vector<double> w(outerToInner);
    w.push_back(1.0 - 2.0 * sum);
    for (auto it = outerToInner.rbegin(); it != outerToInner.rend(); ++it) w.push_back(*it);
    return w;
}

}  // namespace

bool isComposition(Method method) {
    switch (method) {
        case Method::Verlet:
        case Method::ForestRuth:
        case Method::Pefrl:
        case Method::BlanesMoan:
        case Method::Yoshida6:
        case Method::Yoshida8: return true;
        default: return false;
    }
}

SymplecticComposition compositionFor(Method method) {
    switch (method) {
        case Method::Verlet: return verletSteps({1.0}, 2);
        case Method::ForestRuth: {
            // E. Forest, R. D. Ruth, Physica D 43, 105 (1990); H. Yoshida, Phys. Lett. A 150, 262 (1990):
            // theta = 1 / (2 - 2^(1/3)).
            const double theta = 1.0 / (2.0 - std::cbrt(2.0));
            return verletSteps({theta, 1.0 - 2.0 * theta, theta}, 4);
        }
        case Method::Pefrl: {
            // I. P. Omelyan, I. M. Mryglod, R. Folk, Comput. Phys. Commun. 146, 188 (2002), eq. (20).
            const double xi = 0.1786178958448091, lambda = -0.2123418310626054, chi = -0.06626458266981849;
            SymplecticComposition c;
            c.order = 4;
            c.ops = {{CompositionOp::Drift, xi},     {CompositionOp::Kick, 0.5 * (1 - 2 * lambda)},
                     {CompositionOp::Drift, chi},    {CompositionOp::Kick, lambda},
                     {CompositionOp::Drift, 1 - 2 * (chi + xi)},
                     {CompositionOp::Kick, lambda},  {CompositionOp::Drift, chi},
                     {CompositionOp::Kick, 0.5 * (1 - 2 * lambda)}, {CompositionOp::Drift, xi}};
            return c;
        }
        case Method::BlanesMoan: {
            // S. Blanes, P. C. Moan, J. Comput. Appl. Math. 142, 313 (2002), Table 3, SRKN_6^b:
            // b1 A a1 B b2 A a2 B b3 A a3 B b4 A a3 B b3 A a2 B b2 A a1 B b1 (kicks b, drifts a).
            const double a1 = 0.245298957184271, a2 = 0.604872665711080, a3 = 0.5 - a1 - a2;
            const double b1 = 0.0829844064174052, b2 = 0.396309801498368, b3 = -0.0390563049223486;
            const double b4 = 1.0 - 2.0 * (b1 + b2 + b3);
            SymplecticComposition c;
            c.order = 4;
            c.ops = {{CompositionOp::Kick, b1},  {CompositionOp::Drift, a1}, {CompositionOp::Kick, b2},  {CompositionOp::Drift, a2},
                     {CompositionOp::Kick, b3},  {CompositionOp::Drift, a3}, {CompositionOp::Kick, b4},  {CompositionOp::Drift, a3},
                     {CompositionOp::Kick, b3},  {CompositionOp::Drift, a2}, {CompositionOp::Kick, b2},  {CompositionOp::Drift, a1},
                     {CompositionOp::Kick, b1}};
            return c;
        }
        case Method::Yoshida6:
            // H. Yoshida, Phys. Lett. A 150, 262 (1990), Table 1, solution A (w3, w2, w1; w0 = 1 - 2 sum).
            return verletSteps(symmetric({0.784513610477560, 0.235573213359357, -1.17767998417887}), 6);
        case Method::Yoshida8:
            // Yoshida (1990), Table 2, solution D (w7 .. w1; w0 = 1 - 2 sum).
            return verletSteps(symmetric({0.914844246229740, 0.253693336566229, -1.44485223686048, -0.158240635368243,
                                          1.93813913762276, -1.96061023297549, 0.102799849391985}),
                               8);
        default: break;
    }
    throw std::invalid_argument("a Runge-Kutta method is not a symplectic composition");
}

int forcePassesPerStep(const SymplecticComposition& composition) {
    int passes = 0;
    bool moved = false;
    for (const CompositionOp& op : composition.ops) {
        if (op.kind == CompositionOp::Drift) moved = true;
        else if (moved) {
            ++passes;
            moved = false;
        }
    }
    return passes;
}

double linearStabilityLimit(const SymplecticComposition& composition) {
    // The trace of one step at omega*dt = h: drifts [[1, c h], [0, 1]], kicks [[1, 0], [-d h, 1]].
    auto trace = [&](double h) {
        double m00 = 1, m01 = 0, m10 = 0, m11 = 1;
        for (const CompositionOp& op : composition.ops) {
            const double k = op.weight * h;
            if (op.kind == CompositionOp::Drift) {
                m00 += k * m10;
                m01 += k * m11;
            } else {
                m10 -= k * m00;
                m11 -= k * m01;
            }
        }
        return m00 + m11;
    };
    // The first h where |trace| exceeds 2, found on a fine scan and refined by bisection.
    constexpr double kScan = 1e-3;
    for (double h = kScan; h < 20.0; h += kScan) {
        if (std::fabs(trace(h)) <= 2.0) continue;
        double lo = h - kScan, hi = h;
        for (int k = 0; k < 50; ++k) {
            const double mid = 0.5 * (lo + hi);
            (std::fabs(trace(mid)) <= 2.0 ? lo : hi) = mid;
        }
        return lo;
    }
    return INFINITY;
}

double compositionStabilityLimit(Method method) { return linearStabilityLimit(compositionFor(method)); }

}  // namespace corebox
