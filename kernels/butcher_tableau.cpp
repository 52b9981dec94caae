#include "butcher_tableau.h"

#include <stdexcept>

namespace corebox {
namespace {

void finish(ButcherTableau& t) {
    t.solutionStages = t.stages;
    while (t.solutionStages > 1 && t.b[t.solutionStages - 1] == 0.0) --t.solutionStages;
}

}  // namespace

ButcherTableau eulerTableau() {
    ButcherTableau t;
    t.stages = 1;
    t.order = 1;
    t.b[0] = 1;
    finish(t);
    return t;
}

ButcherTableau rk2MidpointTableau() {
    ButcherTableau t;
    t.stages = 2;
    t.order = 2;
    t.c[1] = 0.5;
    t.a[1][0] = 0.5;
    t.b[1] = 1;
    finish(t);
    return t;
}

ButcherTableau rk4Tableau() {
    ButcherTableau t;
    t.stages = 4;
    t.order = 4;
    t.c[1] = t.c[2] = 0.5;
    t.c[3] = 1;
    t.a[1][0] = 0.5;
    t.a[2][1] = 0.5;
    t.a[3][2] = 1;
    t.b[0] = t.b[3] = 1.0 / 6.0;
    t.b[1] = t.b[2] = 1.0 / 3.0;
    finish(t);
    return t;
}

// Dormand & Prince, "A family of embedded Runge-Kutta formulae", J. Comp. Appl. Math. 6 (1980).
ButcherTableau dormandPrince5Tableau() {
    ButcherTableau t;
    t.stages = 7;
    t.order = 5;
    t.embeddedOrder = 4;
    const double c[7] = {0, 1.0 / 5, 3.0 / 10, 4.0 / 5, 8.0 / 9, 1, 1};
    const double a[7][6] = {
        {},
        {1.0 / 5},
        {3.0 / 40, 9.0 / 40},
        {44.0 / 45, -56.0 / 15, 32.0 / 9},
        {19372.0 / 6561, -25360.0 / 2187, 64448.0 / 6561, -212.0 / 729},
        {9017.0 / 3168, -355.0 / 33, 46732.0 / 5247, 49.0 / 176, -5103.0 / 18656},
        {35.0 / 384, 0, 500.0 / 1113, 125.0 / 192, -2187.0 / 6784, 11.0 / 84},
    };
    const double b5[7] = {35.0 / 384, 0, 500.0 / 1113, 125.0 / 192, -2187.0 / 6784, 11.0 / 84, 0};
    const double b4[7] = {5179.0 / 57600, 0, 7571.0 / 16695, 393.0 / 640, -92097.0 / 339200, 187.0 / 2100, 1.0 / 40};
    for (int i = 0; i < 7; ++i) {
        t.c[i] = c[i];
        for (int j = 0; j < i; ++j) t.a[i][j] = a[i][j];
        t.b[i] = b5[i];
        t.bError[i] = b5[i] - b4[i];
    }
    finish(t);
    return t;
}

ButcherTableau hairer10Tableau() {
    ButcherTableau t;
    t.stages = 17;
    t.order = 10;
#include "hairer10_coefficients.inc"
    finish(t);
    return t;
}

ButcherTableau tableauFor(Method method) {
    switch (method) {
        case Method::Euler: return eulerTableau();
        case Method::Rk2: return rk2MidpointTableau();
        case Method::Rk4: return rk4Tableau();
        case Method::Dp5: return dormandPrince5Tableau();
        case Method::Hairer10: return hairer10Tableau();
        case Method::Verlet:
        case Method::ForestRuth:
        case Method::Pefrl:
        case Method::BlanesMoan:
        case Method::Yoshida6:
        case Method::Yoshida8: break;
    }
    throw std::invalid_argument("velocity Verlet and its compositions are not Runge-Kutta methods and have no Butcher tableau");
}

}  // namespace corebox
