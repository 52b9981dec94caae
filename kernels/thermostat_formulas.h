// Thermostat formulas on the total kinetic energy K with N_f degrees of freedom and target
// K_t = N_f kT / 2. Both return the velocity scale factor alpha = sqrt(K_new / K).
//
// Bussi, Donadio & Parrinello, J. Chem. Phys. 126, 014101 (2007), eq. (A7): with c = exp(-dt/tau),
//   K_new = c K + (1 - c) K_t (R1^2 + S) / N_f + 2 R1 sqrt(c (1 - c) K K_t / N_f)
// where R1 ~ N(0,1) and S is a sum of N_f - 1 squared standard normals. It samples the canonical
// distribution of K exactly, for any tau.
#pragma once

#include <cmath>

#include "hd.h"

namespace corebox {

COREBOX_HD inline double bussiKineticEnergy(double kinetic, double targetKinetic, double degreesOfFreedom,
                                            double decay, double r1, double sumSquares) {
    return decay * kinetic + (1.0 - decay) * targetKinetic * (r1 * r1 + sumSquares) / degreesOfFreedom +
           2.0 * r1 * sqrt(decay * (1.0 - decay) * kinetic * targetKinetic / degreesOfFreedom);
}

// Berendsen-style weak coupling; tau <= dt rescales to the target exactly.
COREBOX_HD inline double rescaleKineticEnergy(double kinetic, double targetKinetic, double dt, double tau) {
    if (tau <= dt) return targetKinetic;
    return kinetic + (dt / tau) * (targetKinetic - kinetic);
}

}  // namespace corebox
