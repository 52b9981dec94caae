#include "speed_statistics.h"

#include <algorithm>
#include <cmath>

#include "maxwell_boltzmann.h"

namespace corebox {

SpeedStatistics computeSpeedStatistics(std::vector<double> speeds, const std::vector<int64_t>& countsPerSpecies,
                                       const std::vector<double>& masses, const SpeedRequest& request) {
    SpeedStatistics out;
    out.species = request.species;
    out.count = int64_t(speeds.size());
    out.maxSpeed = request.maxSpeed;
    out.histogram.assign(size_t(std::max(request.bins, 1)), 0);
    const double binWidth = request.maxSpeed / double(out.histogram.size());
    for (double v : speeds) {
        const int64_t bin = int64_t(v / binWidth);
        if (bin >= 0 && bin < int64_t(out.histogram.size())) ++out.histogram[size_t(bin)];
    }
    if (speeds.empty() || request.temperature <= 0) return out;
    std::sort(speeds.begin(), speeds.end());
    const double n = double(speeds.size());
    std::vector<double> weights(masses.size());
    for (size_t s = 0; s < masses.size(); ++s) weights[s] = double(countsPerSpecies[s]) / n;
    auto cdf = [&](double v) { return maxwellBoltzmannMixtureCdf(v, weights.data(), masses.data(), int(masses.size()), request.temperature); };
    double d = 0;
    for (size_t i = 0; i < speeds.size(); ++i) {
        const double f = cdf(speeds[i]);
        d = std::max({d, f - double(i) / n, double(i + 1) / n - f});
    }
    out.ksStatistic = d;
    return out;
}

SpeedStatistics speedStatisticsOf(const ParticleState& state, const std::vector<SpeciesDef>& species, const SpeedRequest& request) {
    std::vector<double> speeds;
    std::vector<int64_t> perSpecies(species.size(), 0);
    for (size_t i = 0; i < state.size(); ++i) {
        if (request.species >= 0 && state.species[i] != request.species) continue;
        speeds.push_back(std::sqrt(norm2(state.velocity[i])));
        ++perSpecies[size_t(state.species[i])];
    }
    std::vector<double> masses;
    for (const SpeciesDef& s : species) masses.push_back(s.mass);
    return computeSpeedStatistics(std::move(speeds), perSpecies, masses, request);
}

double ksCriticalValue(int64_t n, double alpha) {
    const double sn = std::sqrt(double(n));
    return std::sqrt(-0.5 * std::log(alpha / 2.0)) / (sn + 0.12 + 0.11 / sn);
}

}  // namespace corebox
