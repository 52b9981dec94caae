// Symplectic compositions of velocity Verlet (DESIGN.md sec. 2): a step is a fixed sequence of drifts
// x += c dt v and kicks v += d dt a(x), run by the core's integration driver on any backend's kick()
// and drift() (src/core/integration_driver.cpp). A kick right after another, or at the start of a step
// whose positions have not moved since the last force pass, reuses the accelerations (first same as
// last), so the force passes per step are the kicks that follow a drift.
//
// The methods, with the sources of their coefficients (symplectic_composition.cpp):
//   verlet       kick 1/2, drift 1, kick 1/2 (order 2)
//   forest_ruth  Forest & Ruth (1990) = Yoshida's (1990) triple jump of Verlet, order 4
//   pefrl        Omelyan, Mryglod & Folk (2002), position-extended Forest-Ruth-like, order 4
//   blanes_moan  Blanes & Moan (2002), SRKN_6^b (BAB, 6 stages), order 4
//   yoshida6     Yoshida (1990), solution A: 7 Verlet steps, order 6
//   yoshida8     Yoshida (1990), solution D: 15 Verlet steps, order 8
#pragma once

#include <vector>

#include "butcher_tableau.h"

namespace corebox {

struct CompositionOp {
    enum Kind { Drift, Kick } kind;
    double weight;  // fraction of dt
};

struct SymplecticComposition {
    std::vector<CompositionOp> ops;
    int order = 0;
};

bool isComposition(Method method);  // verlet and the compositions above
// Throws std::invalid_argument for a Runge-Kutta method.
SymplecticComposition compositionFor(Method method);
// Force passes per step in a long run (kicks after a drift; the first kick reuses the last one's).
int forcePassesPerStep(const SymplecticComposition& composition);
// The largest omega*dt at which the composition is stable on the harmonic oscillator x'' = -omega^2 x
// (one step is a 2x2 matrix of determinant 1; stable while |trace| <= 2), from its coefficients.
double linearStabilityLimit(const SymplecticComposition& composition);
double compositionStabilityLimit(Method method);

}  // namespace corebox
