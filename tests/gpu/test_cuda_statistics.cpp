// Statistical mechanics on the GPU at N = 10^5: an elastic hard-sphere gas started with equal
// speeds relaxes to Maxwell-Boltzmann (KS test at alpha = 0.01, computed on the GPU), and the Bussi
// thermostat holds its target (mean within 2%, canonical kinetic-energy fluctuations within 20%).
#include <cmath>
#include <vector>

#include "gpu_fixture.h"
#include "initial_conditions.h"
#include "simulation.h"
#include "speed_statistics.h"

using namespace corebox;

namespace {

Scene gas(int64_t n) {
    Scene scene;
    SpeciesDef s;
    s.name = "A";
    s.count = n;
    s.epsilon = 0;
    scene.species = {s};
    const double box = std::cbrt(double(n) * 0.5236 / 0.1);  // packing fraction 0.1
    scene.box.size = {box, box, box};
    scene.integrator.method = Method::Verlet;
    scene.integrator.dt = 0.01;
    scene.thermostat.kind = ThermostatKind::None;
    return scene;
}

}  // namespace

TEST(CudaStatistics, HardSphereGasRelaxesToMaxwellBoltzmannAtOneHundredThousand) {
    COREBOX_REQUIRE_GPU();
    const Scene scene = gas(100000);
    ParticleState st = makeInitialState(scene);
    for (auto& v : st.velocity) v = (std::sqrt(3.0) / std::sqrt(norm2(v))) * v;
    Simulation sim(scene, makeCudaBackend(CudaBackendOptions{Precision::Fp64, 0}), st);
    const double t = sim.observe().temperature;
    SpeedRequest request;
    request.temperature = t;
    const double critical = ksCriticalValue(100000, 0.01);
    EXPECT_GT(sim.speedStatistics(request).ksStatistic, 10 * critical);
    for (int s = 0; s < 1500; ++s) sim.step();
    request.temperature = sim.observe().temperature;
    EXPECT_NEAR(request.temperature, t, 1e-9 * t);
    const double d = sim.speedStatistics(request).ksStatistic;
    RecordProperty("ks_after", std::to_string(d));
    RecordProperty("ks_critical", std::to_string(critical));
    EXPECT_LT(d, critical);
}

TEST(CudaStatistics, BussiHoldsTheTargetAtOneHundredThousand) {
    COREBOX_REQUIRE_GPU();
    Scene scene = gas(100000);
    scene.thermostat.kind = ThermostatKind::Bussi;
    scene.thermostat.temperature = 1.5;
    scene.thermostat.tau = 0.05;
    Simulation sim(scene, makeCudaBackend(CudaBackendOptions{Precision::Fp64, 0}), makeInitialState(scene));
    std::vector<double> kinetic;
    for (int s = 1; s <= 3000; ++s) {
        sim.step();
        if (s > 500 && s % 5 == 0) kinetic.push_back(sim.lastKineticEnergy());
    }
    double mean = 0, var = 0;
    for (double k : kinetic) mean += k;
    mean /= double(kinetic.size());
    for (double k : kinetic) var += (k - mean) * (k - mean);
    var /= double(kinetic.size() - 1);
    const double nf = 3.0e5;
    RecordProperty("mean_temperature", std::to_string(2 * mean / nf));
    RecordProperty("sd_over_canonical", std::to_string(std::sqrt(var) / (std::sqrt(nf / 2) * 1.5)));
    EXPECT_NEAR(2 * mean / nf, 1.5, 0.02 * 1.5);
    EXPECT_NEAR(std::sqrt(var) / (std::sqrt(nf / 2) * 1.5), 1.0, 0.2);
}
