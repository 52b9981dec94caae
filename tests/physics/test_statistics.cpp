// Statistical mechanics with fixed seeds and stated significance levels: relaxation of an elastic
// hard-sphere gas to Maxwell-Boltzmann (KS test), equipartition between species of different mass,
// and the Bussi thermostat's mean and canonical fluctuations. The simulations run on each backend
// present (cpu, cuda) with the same bounds. The initial states and the thermostat's draws are the
// same on every backend (counter-based), but the dynamics is chaotic: a GPU run, whose round-off
// differs from the CPU's, follows another trajectory of the same ensemble, so each of its statistical
// checks can fail by chance with the stated alpha, like the CPU's. The check of the reference
// distribution itself (last test) involves no backend and runs once.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "maxwell_boltzmann.h"
#include "physics_fixtures.h"
#include "speed_statistics.h"

using namespace corebox;
using namespace corebox::testing;

namespace {

// Hard spheres of radius 0.5 at packing fraction ~0.1, every speed equal to sqrt(3 kT / m) with
// directions from the counter-based initial velocities (normalised).
ParticleState equalSpeeds(const Scene& scene, double temperature) {
    ParticleState st = makeInitialState(scene);
    for (size_t i = 0; i < st.size(); ++i) {
        const double m = scene.species[size_t(st.species[i])].mass;
        const double speed = std::sqrt(3.0 * temperature / m);
        st.velocity[i] = (speed / std::sqrt(norm2(st.velocity[i]))) * st.velocity[i];
    }
    return st;
}

class Statistics : public OnEveryBackend {};

}  // namespace

INSTANTIATE_TEST_SUITE_P(Backends, Statistics, ::testing::ValuesIn(backendNames()), backendInstanceName);

TEST_P(Statistics, ElasticHardSphereGasRelaxesToMaxwellBoltzmann) {
    Scene scene = hardSphereScene(2000, 22.0, Method::Verlet, 0.01);
    const ParticleState start = equalSpeeds(scene, 1.0);
    auto sim = makeSimulation(backendName(), scene, start);
    const double temperature = sim->observe().temperature;
    SpeedRequest request;
    request.temperature = temperature;
    const double critical = ksCriticalValue(2000, 0.01);
    const double before = sim->speedStatistics(request).ksStatistic;
    EXPECT_GT(before, 5 * critical);            // all speeds equal: far from MB, so the test can fail
    for (int s = 0; s < 800; ++s) sim->step();  // ~10 collision times
    const ObservablesRow row = sim->observe();
    EXPECT_NEAR(row.temperature, temperature, 1e-9 * temperature);  // elastic: T conserved
    request.temperature = row.temperature;
    const SpeedStatistics after = sim->speedStatistics(request);
    RecordProperty("ks_before", std::to_string(before));
    RecordProperty("ks_after", std::to_string(after.ksStatistic));
    EXPECT_LT(after.ksStatistic, critical)
        << "KS D = " << after.ksStatistic << " vs D_crit(alpha = 0.01) = " << critical;
}

TEST_P(Statistics, SpeciesOfMassRatioFourShareOneTemperature) {
    Scene scene = hardSphereScene(0, 22.0, Method::Verlet, 0.01);
    SpeciesDef light = scene.species[0], heavy = scene.species[0];
    light.name = "light";
    light.count = 1000;
    heavy.name = "heavy";
    heavy.count = 1000;
    heavy.mass = 4.0;
    scene.species = {light, heavy};
    ParticleState st = equalSpeeds(scene, 1.0);
    for (size_t i = 0; i < st.size(); ++i) {  // heavy ones start three times hotter
        if (st.species[i] == 1) st.velocity[i] = std::sqrt(3.0) * st.velocity[i];
    }
    auto sim = makeSimulation(backendName(), scene, st);
    const ObservablesRow first = sim->observe();
    EXPECT_GT(first.speciesTemperature[1] / first.speciesTemperature[0], 2.5);
    double sumLight = 0, sumHeavy = 0;
    int samples = 0;
    for (int s = 1; s <= 1200; ++s) {
        sim->step();
        if (s > 600 && s % 10 == 0) {  // time average over the second half damps the 2.6% snapshot noise
            const ObservablesRow row = sim->observe();
            sumLight += row.speciesTemperature[0];
            sumHeavy += row.speciesTemperature[1];
            ++samples;
        }
    }
    const double ratio = sumHeavy / sumLight;
    RecordProperty("temperature_ratio", std::to_string(ratio));
    EXPECT_NEAR(ratio, 1.0, 0.03);
}

TEST_P(Statistics, BussiHoldsTheTargetWithCanonicalFluctuations) {
    // A dilute LJ gas (rho = 0.125) at T = 1.5: the mean temperature within 2% of the target and
    // the standard deviation of the kinetic energy within 20% of the canonical sqrt(N_f / 2) kT.
    Scene scene;
    SpeciesDef s;
    s.name = "Ar";
    s.count = 216;
    s.radius = 0.4;
    scene.species = {s};
    scene.box.size = {12, 12, 12};
    scene.interaction.cutoff = 2.5;
    scene.integrator.method = Method::Verlet;
    scene.integrator.dt = 0.005;
    scene.thermostat.kind = ThermostatKind::Bussi;
    scene.thermostat.temperature = 1.5;
    scene.thermostat.tau = 0.05;
    scene.init.temperature = 1.0;
    auto sim = makeSimulation(backendName(), scene);
    std::vector<double> kinetic;
    for (int step = 1; step <= 24000; ++step) {
        sim->step();
        if (step > 2000 && step % 10 == 0) kinetic.push_back(sim->lastKineticEnergy());
    }
    double mean = 0, var = 0;
    for (double k : kinetic) mean += k;
    mean /= double(kinetic.size());
    for (double k : kinetic) var += (k - mean) * (k - mean);
    var /= double(kinetic.size() - 1);
    const double nf = 3.0 * 216;
    const double meanT = 2 * mean / nf;
    const double canonicalSd = std::sqrt(nf / 2) * 1.5;
    RecordProperty("mean_temperature", std::to_string(meanT));
    RecordProperty("sd_over_canonical", std::to_string(std::sqrt(var) / canonicalSd));
    EXPECT_NEAR(meanT, 1.5, 0.02 * 1.5);
    EXPECT_NEAR(std::sqrt(var) / canonicalSd, 1.0, 0.2);
}

// No backend: the KS statistic and the Maxwell-Boltzmann CDF are host code (speed_statistics.h).
TEST(Statistics, KsStatisticOfAnExactMaxwellBoltzmannSampleIsSmall) {
    // The reference itself: inverse-CDF samples at evenly spaced quantiles have D = 1/(2n).
    std::vector<double> speeds;
    const int n = 1000;
    for (int i = 0; i < n; ++i) {
        const double q = (i + 0.5) / n;
        double lo = 0, hi = 10;
        for (int it = 0; it < 100; ++it) {
            const double mid = 0.5 * (lo + hi);
            if (maxwellBoltzmannCdf(mid, 2.0, 1.3) < q)
                lo = mid;
            else
                hi = mid;
        }
        speeds.push_back(0.5 * (lo + hi));
    }
    SpeedRequest request;
    request.temperature = 1.3;
    const SpeedStatistics st = computeSpeedStatistics(speeds, {n}, {2.0}, request);
    EXPECT_NEAR(st.ksStatistic, 0.5 / n, 1e-9);
    request.temperature = 1.6;  // the wrong temperature is rejected
    EXPECT_GT(computeSpeedStatistics(speeds, {n}, {2.0}, request).ksStatistic, ksCriticalValue(n, 0.01));
}
