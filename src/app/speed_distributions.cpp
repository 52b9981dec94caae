#include "speed_distributions.h"

#include <algorithm>
#include <cmath>

#include "maxwell_boltzmann.h"
#include "speed_statistics.h"

namespace corebox {

void measureSpeedDistributions(Simulation& sim, const ObservablesRow& row, SpeedDistributionData& speeds, int bins) {
    const Scene& scene = sim.scene();
    double lightest = 0, hottest = scene.init.temperature;
    if (scene.thermostat.kind != ThermostatKind::None) hottest = std::max(hottest, scene.thermostat.temperature);
    for (const SpeciesDef& s : scene.species) {
        if (s.count > 0) lightest = lightest == 0 ? s.mass : std::min(lightest, s.mass);
    }
    speeds.maxSpeed = 3.5 * std::sqrt(std::max(hottest, row.temperature) / std::max(lightest, 1e-12));
    speeds.targetTemperature = scene.thermostat.kind == ThermostatKind::None ? 0.0 : scene.thermostat.temperature;
    speeds.species.clear();
    const ParticleState state = sim.state();  // one download for every series
    auto series = [&](int species, const std::string& name, std::array<float, 3> color, double mass, double temperature) {
        SpeedRequest request;
        request.species = species;
        request.bins = bins;
        request.maxSpeed = speeds.maxSpeed;
        request.temperature = temperature;
        const SpeedStatistics st = speedStatisticsOf(state, scene.species, request);
        SpeedSeries out;
        out.name = name;
        out.color = color;
        out.mass = mass;
        out.count = st.count;
        out.ksStatistic = st.ksStatistic;
        out.ksCritical = st.count > 0 ? ksCriticalValue(st.count, 0.01) : 0.0;
        out.temperatureEquipartition = temperature;
        const double width = speeds.maxSpeed / bins;
        double meanSpeed = 0;
        for (int b = 0; b < bins; ++b) {
            out.density.push_back(st.count > 0 ? float(double(st.histogram[size_t(b)]) / (double(st.count) * width)) : 0.0f);
            meanSpeed += (b + 0.5) * width * double(st.histogram[size_t(b)]);
        }
        if (st.count > 0) meanSpeed /= double(st.count);
        out.temperatureDistribution = temperatureFromMeanSpeed(meanSpeed, mass);
        return out;
    };
    int64_t total = 0;
    for (size_t s = 0; s < scene.species.size(); ++s) total += scene.species[s].count;
    for (size_t s = 0; s < scene.species.size(); ++s) {
        if (scene.species[s].count == 0) continue;
        const double t = s < row.speciesTemperature.size() ? row.speciesTemperature[s] : row.temperature;
        speeds.species.push_back(series(int(s), scene.species[s].name, scene.species[s].color, scene.species[s].mass, t));
    }
    if (scene.species.size() > 1) {
        SpeedSeries all = series(-1, "all", {0.85f, 0.85f, 0.9f}, scene.species[0].mass, row.temperature);
        for (const SpeciesDef& s : scene.species) {
            if (s.count > 0) all.mixture.push_back({double(s.count) / double(total), s.mass});
        }
        // The mean speed of a mixture: <v> = sum_k w_k sqrt(8 kT / (pi m_k)); solve for T.
        double meanFactor = 0;
        for (const auto& wm : all.mixture) meanFactor += wm[0] * std::sqrt(8.0 / (M_PI * wm[1]));
        double meanSpeed = 0, width = speeds.maxSpeed / bins;
        for (size_t b = 0; b < all.density.size(); ++b) meanSpeed += (double(b) + 0.5) * width * double(all.density[b]) * width;
        all.temperatureDistribution = meanFactor > 0 ? std::pow(meanSpeed / meanFactor, 2) : 0.0;
        speeds.species.push_back(all);
    }
}

}  // namespace corebox
