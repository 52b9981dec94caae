// Speed distribution against Maxwell-Boltzmann: histogram and Kolmogorov-Smirnov statistic.
// For all species together the reference is the mixture sum_s (n_s / n) F_s(v) at one temperature.
#pragma once

#include <cstdint>
#include <vector>

#include "particle_state.h"
#include "scene.h"

namespace corebox {

struct SpeedStatistics {
    int species = -1;                // -1: all particles
    int64_t count = 0;
    std::vector<int64_t> histogram;  // counts per bin over [0, maxSpeed)
    double maxSpeed = 0;
    double ksStatistic = 0;          // Kolmogorov-Smirnov D against MB at the given temperature
};

struct SpeedRequest {
    int species = -1;
    int bins = 40;
    double maxSpeed = 4.0;
    double temperature = 1.0;  // MB reference temperature; the masses come from the species table
};

// The statistics of the particles of `request.species` (all when -1) in `state`.
SpeedStatistics speedStatisticsOf(const ParticleState& state, const std::vector<SpeciesDef>& species, const SpeedRequest& request);

// speeds: the sample (any order; sorted here). countsPerSpecies/masses: the sample's makeup, for the
// mixture reference.
SpeedStatistics computeSpeedStatistics(std::vector<double> speeds, const std::vector<int64_t>& countsPerSpecies,
                                       const std::vector<double>& masses, const SpeedRequest& request);

// KS critical value for sample size n at significance alpha (asymptotic, Smirnov): D_crit =
// sqrt(-ln(alpha / 2) / 2) / (sqrt(n) + 0.12 + 0.11 / sqrt(n)) (Stephens' small-n correction).
double ksCriticalValue(int64_t n, double alpha);

}  // namespace corebox
