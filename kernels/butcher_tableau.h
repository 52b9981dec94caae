// Explicit Runge-Kutta methods as Butcher tables, run by one stepping routine (src/cpu and the CUDA
// kernels both read this struct). Coefficients are stored in double whatever the run precision:
// Hairer's order-10 table loses its order if its coefficients are rounded to float.
//
//   stage i:  Y_i = y + dt * sum_{j<i} a_ij K_j,   K_i = f(Y_i)
//   result:   y' = y + dt * sum_i b_i K_i
//   error:    dt * sum_i bError_i K_i  (b - b_hat of the embedded pair), when embedded
#pragma once

#include "hd.h"

namespace corebox {

constexpr int kMaxStages = 17;

// The Runge-Kutta methods (a Butcher tableau each), velocity Verlet and its symplectic compositions
// (symplectic_composition.h).
enum class Method : int { Euler = 0, Rk2, Rk4, Dp5, Hairer10, Verlet, ForestRuth, Pefrl, BlanesMoan, Yoshida6, Yoshida8 };

struct ButcherTableau {
    int stages = 0;
    int order = 0;
    int embeddedOrder = 0;  // 0 when the method carries no error estimate
    double c[kMaxStages] = {};
    double a[kMaxStages][kMaxStages] = {};
    double b[kMaxStages] = {};
    double bError[kMaxStages] = {};
    // Stages the fixed-step solution needs: trailing stages with b_i = 0 (DP5's 7th, only used by
    // the error estimate) are skipped when no estimate is wanted.
    int solutionStages = 0;
};

ButcherTableau eulerTableau();
ButcherTableau rk2MidpointTableau();
ButcherTableau rk4Tableau();
ButcherTableau dormandPrince5Tableau();
// Hairer (1978), 17 stages, order 10; generated at build time from kernels/hairer10_tableau.tsv.
ButcherTableau hairer10Tableau();

// The tableau of an explicit RK method; Verlet and its compositions have none (not Runge-Kutta methods).
ButcherTableau tableauFor(Method method);

}  // namespace corebox
