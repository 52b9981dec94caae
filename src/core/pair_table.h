// Species-pair coefficient table (S x S, row-major) from the scene: Lorentz-Berthelot-style
// combination sigma_ij = (sigma_i + sigma_j) / 2, eps_ij = sqrt(eps_i eps_j), the mixing x_ij, and
// the cutoff shifts. Built in double on the host; backends convert to their precision.
#pragma once

#include <vector>

#include "pair_potential.h"
#include "scene.h"

namespace corebox {

std::vector<PairCoefficients<double>> buildPairTable(const StepParameters& parameters);

template <class Real>
std::vector<PairCoefficients<Real>> convertPairTable(const std::vector<PairCoefficients<double>>& table) {
    std::vector<PairCoefficients<Real>> out(table.size());
    for (size_t k = 0; k < table.size(); ++k) {
        const PairCoefficients<double>& p = table[k];
        out[k] = PairCoefficients<Real>{Real(p.sigma2), Real(p.eps4), Real(p.mixing), Real(p.cutoff2),
                                        Real(p.energyShift), Real(p.forceAtCutoff), Real(p.cutoff), p.shift};
    }
    return out;
}

}  // namespace corebox
