#include "pair_table.h"

#include <cmath>

namespace corebox {

std::vector<PairCoefficients<double>> buildPairTable(const StepParameters& parameters) {
    const size_t s = parameters.species.size();
    const InteractionDef& in = parameters.interaction;
    std::vector<PairCoefficients<double>> table(s * s);
    for (size_t i = 0; i < s; ++i) {
        for (size_t j = 0; j < s; ++j) {
            const SpeciesDef& a = parameters.species[i];
            const SpeciesDef& b = parameters.species[j];
            PairCoefficients<double>& p = table[i * s + j];
            const double sigma = 0.5 * (a.sigma + b.sigma);
            p.sigma2 = sigma * sigma;
            p.eps4 = 4.0 * std::sqrt(a.epsilon * b.epsilon);
            p.mixing = in.mixing.empty() ? 1.0 : in.mixing[i][j];
            p.cutoff = in.cutoff;
            p.cutoff2 = in.cutoff * in.cutoff;
            p.shift = int(in.shift);
            computeCutoffShift(p.sigma2, p.eps4, p.mixing, in.cutoff, in.shift, &p.energyShift, &p.forceAtCutoff);
        }
    }
    return table;
}

}  // namespace corebox
