// Speed distribution against Maxwell-Boltzmann: histogram and Kolmogorov-Smirnov statistic.
// For all species together the reference is the mixture sum_s (n_s / n) F_s(v) at one temperature.
#pragma once

#include <cstdint>
#include <vector>

#include "backend.h"

namespace corebox {

// speeds: the sample (any order; sorted here). countsPerSpecies/masses: the sample's makeup, for the
// mixture reference.
SpeedStatistics computeSpeedStatistics(std::vector<double> speeds, const std::vector<int64_t>& countsPerSpecies,
                                       const std::vector<double>& masses, const SpeedRequest& request);

// KS critical value for sample size n at significance alpha (asymptotic, Smirnov): D_crit =
// sqrt(-ln(alpha / 2) / 2) / (sqrt(n) + 0.12 + 0.11 / sqrt(n)) (Stephens' small-n correction).
double ksCriticalValue(int64_t n, double alpha);

}  // namespace corebox
