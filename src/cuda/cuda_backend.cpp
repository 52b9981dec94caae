#include "cuda_backend.h"

#include <algorithm>
#include <cmath>
#include <type_traits>
#include <vector>

#include "cuda_check.h"
#include "device_buffer.h"
#include "device_partition.h"
#include "gpu_launch.h"
#include "pair_table.h"
#include "rk_stage.h"
#include "step_driver.h"

namespace corebox {

int cudaDeviceCount() {
    int count = 0;
    if (cudaGetDeviceCount(&count) != cudaSuccess) {
        cudaGetLastError();  // clear the sticky "no driver" error
        return 0;
    }
    return count;
}

std::string cudaDeviceDescription(int device) {
    cudaDeviceProp prop{};
    if (cudaGetDeviceProperties(&prop, device) != cudaSuccess) return "unknown CUDA device";
    int driver = 0, runtime = 0;
    cudaDriverGetVersion(&driver);
    cudaRuntimeGetVersion(&runtime);
    return std::string(prop.name) + " (CUDA driver " + std::to_string(driver / 1000) + "." + std::to_string((driver % 1000) / 10) +
           ", runtime " + std::to_string(runtime / 1000) + "." + std::to_string((runtime % 1000) / 10) + ")";
}

namespace {

template <class Real>
class CudaBackendImpl final : public Backend, public CudaParticleSource {
public:
    explicit CudaBackendImpl(const CudaBackendOptions& options) : m_device(options.device), m_partition({options.device}, 0) {
        if (options.device < 0 || options.device >= cudaDeviceCount()) {
            throw DeviceError("CUDA device " + std::to_string(options.device) + " is not available (" +
                              std::to_string(cudaDeviceCount()) + " found)");
        }
        for (cudaEvent_t& e : m_phase) cudaCheck(cudaEventCreate(&e), "cudaEventCreate");
        m_counters.resize(2);
        m_kindCounts.resize(3);
        m_healthCounts.resize(3);
        m_healthExamples.resize(5);
    }

    ~CudaBackendImpl() override {
        for (cudaEvent_t e : m_phase) cudaEventDestroy(e);
        for (cudaEvent_t e : m_timingEvents) cudaEventDestroy(e);
    }

    std::string name() const override { return "cuda"; }
    std::string deviceName() const override { return cudaDeviceDescription(m_device); }
    Precision precision() const override { return std::is_same<Real, float>::value ? Precision::Fp32 : Precision::Fp64; }
    int device() const override { return m_device; }

    void setParameters(const StepParameters& parameters) override {
        const bool dtChanged = parameters.integrator.dt != m_params.integrator.dt;
        m_params = parameters;
        if (parameters.integrator.method != Method::Verlet) {
            m_tableau = tableauFor(parameters.integrator.method);
            m_deviceTableau.upload(&m_tableau, 1);
        }
        const std::vector<PairCoefficients<Real>> pairs = convertPairTable<Real>(buildPairTable(parameters));
        m_anyPairForce = std::any_of(pairs.begin(), pairs.end(), [](const PairCoefficients<Real>& p) { return p.eps4 != Real(0); });
        m_pairs.upload(pairs.data(), pairs.size());
        const size_t s = parameters.species.size();
        std::vector<Real> mass(s), invMass(s), radius(s);
        m_maxRadius = 0;
        for (size_t k = 0; k < s; ++k) {
            mass[k] = Real(parameters.species[k].mass);
            invMass[k] = Real(1.0 / parameters.species[k].mass);
            radius[k] = Real(parameters.species[k].radius);
            m_maxRadius = std::max(m_maxRadius, parameters.species[k].radius);
        }
        m_mass.upload(mass.data(), s);
        m_invMass.upload(invMass.data(), s);
        m_radius.upload(radius.data(), s);
        for (int a = 0; a < 3; ++a) {
            m_gravity[a] = Real(parameters.interaction.gravity[size_t(a)]);
            m_box[a] = Real(parameters.box.size[size_t(a)]);
        }
        if (dtChanged || m_dtNext <= 0) m_dtNext = parameters.integrator.dt;
        m_accelerationValid = false;
    }

    void setState(const ParticleState& state) override {
        m_n = int64_t(state.size());
        m_partition.resize(m_n);
        std::vector<Vec3<Real>> x(state.size()), v(state.size());
        for (size_t i = 0; i < state.size(); ++i) {
            x[i] = vec3Cast<Real>(state.position[i]);
            v[i] = vec3Cast<Real>(state.velocity[i]);
        }
        m_x.upload(x.data(), x.size());
        m_v.upload(v.data(), v.size());
        m_species.upload(state.species.data(), state.species.size());
        m_hostSpecies = state.species;
        for (auto* b : {&m_acceleration, &m_xStage, &m_vStage, &m_contactAcceleration, &m_snapshotX, &m_snapshotV}) b->resize(size_t(m_n));
        m_forceScratch.resize(gpu::forceScratchBytes<Real>(m_partition.primary().size(), m_n));
        m_accelerationValid = false;
    }

    ParticleState state() const override { return download(m_x, m_v); }

    StepReport step() override {
        StepReport report;
        m_forceEvents = 0;
        cudaCheck(cudaEventRecord(m_phase[0], stream()), "event");
        integrateStep(*this, m_params.integrator, m_tableau, m_dtNext, report);
        cudaCheck(cudaEventRecord(m_phase[1], stream()), "event");
        resolveCollisions(report);
        cudaCheck(cudaEventRecord(m_phase[2], stream()), "event");
        timePhases(report);
        if (report.pairCollisions + report.wallCollisions + report.positionalFixes > 0) m_accelerationValid = false;
        return report;
    }

    double kineticEnergy() override {
        m_rows.resize(size_t(m_n));
        gpu::launchKineticRow(arrays(), table(), m_rows.data(), stream());
        return sumRows(1)[0];
    }

    void scaleVelocities(double alpha) override { gpu::launchScale(m_v.data(), m_n, Real(alpha), stream()); }

    EnergySums energies() override {
        m_pairEnergy.resize(size_t(m_n));
        gpu::ForceArgs<Real> f = forceArgs(m_x.data(), scratchAcceleration());
        f.pairEnergy = m_pairEnergy.data();
        gpu::launchForces(f, stream());
        const int s = int(m_params.species.size());
        m_rows.resize(size_t(s + 4) * size_t(m_n));
        gpu::launchEnergyRows(gpu::EnergyArgs<Real>{arrays(), table(), m_gravity, m_pairEnergy.data(), m_rows.data()}, stream());
        const std::vector<double> sums = sumRows(s + 4);
        EnergySums e;
        e.kineticPerSpecies.assign(sums.begin(), sums.begin() + s);
        for (double k : e.kineticPerSpecies) e.kinetic += k;
        e.potential = sums[size_t(s)];
        e.momentum = {sums[size_t(s + 1)], sums[size_t(s + 2)], sums[size_t(s + 3)]};
        return e;
    }

    HealthReport health() override {
        cudaCheck(cudaMemsetAsync(m_healthCounts.data(), 0, 3 * sizeof(unsigned long long), stream()), "memset");
        gpu::launchHealth(gpu::HealthArgs<Real>{arrays(), m_box, m_healthCounts.data(), m_healthExamples.data()}, stream());
        unsigned long long counts[3];
        long long examples[5];
        cudaCheck(cudaMemcpyAsync(counts, m_healthCounts.data(), sizeof counts, cudaMemcpyDeviceToHost, stream()), "health");
        cudaCheck(cudaMemcpyAsync(examples, m_healthExamples.data(), sizeof examples, cudaMemcpyDeviceToHost, stream()), "health");
        sync();
        HealthReport r;
        r.nonFinite = int64_t(counts[0]);
        r.outsideBox = int64_t(counts[1]);
        for (unsigned long long k = 0; k < std::min<unsigned long long>(counts[2], 5); ++k) r.examples.push_back(examples[k]);
        std::sort(r.examples.begin(), r.examples.end());
        return r;
    }

    SpeedStatistics speedStatistics(const SpeedRequest& request) override {
        m_speeds.resize(size_t(m_n));
        m_sortedSpeeds.resize(size_t(m_n));
        cudaCheck(cudaMemsetAsync(m_counters.data(), 0, sizeof(unsigned int), stream()), "memset");
        gpu::launchCollectSpeeds(gpu::SpeedArgs<Real>{arrays(), request.species, m_speeds.data(), m_counters.data()}, stream());
        unsigned int count = 0;
        cudaCheck(cudaMemcpyAsync(&count, m_counters.data(), sizeof count, cudaMemcpyDeviceToHost, stream()), "speeds");
        sync();
        SpeedStatistics out;
        out.species = request.species;
        out.count = count;
        out.maxSpeed = request.maxSpeed;
        const int bins = std::max(request.bins, 1);
        out.histogram.assign(size_t(bins), 0);
        if (count == 0) return out;
        m_histogram.resize(size_t(bins));
        cudaCheck(cudaMemsetAsync(m_histogram.data(), 0, size_t(bins) * sizeof(unsigned long long), stream()), "memset");
        gpu::launchHistogram(m_speeds.data(), count, request.maxSpeed / bins, bins, m_histogram.data(), stream());
        std::vector<unsigned long long> hist(static_cast<size_t>(bins));
        cudaCheck(cudaMemcpyAsync(hist.data(), m_histogram.data(), hist.size() * sizeof(unsigned long long), cudaMemcpyDeviceToHost, stream()),
                  "histogram");
        sync();
        for (int b = 0; b < bins; ++b) out.histogram[size_t(b)] = int64_t(hist[size_t(b)]);
        if (request.temperature <= 0) return out;
        // KS against the Maxwell-Boltzmann mixture of the selected species.
        gpu::MixtureArgs mix{};
        std::vector<int64_t> perSpecies(m_params.species.size(), 0);
        for (int32_t s : m_hostSpecies) {
            if (request.species < 0 || s == request.species) ++perSpecies[size_t(s)];
        }
        mix.count = int(std::min<size_t>(perSpecies.size(), 32));
        for (int s = 0; s < mix.count; ++s) {
            mix.weight[s] = double(perSpecies[size_t(s)]) / double(count);
            mix.mass[s] = m_params.species[size_t(s)].mass;
        }
        mix.temperature = request.temperature;
        const size_t scratch = gpu::sortScratchBytes(count);
        m_sortScratch.resize(scratch);
        gpu::sortDoubles(m_speeds.data(), m_sortedSpeeds.data(), count, m_sortScratch.data(), scratch, stream());
        m_partials.resize(size_t(count) / 256 + 1);
        const int blocks = gpu::launchKsPartials(m_sortedSpeeds.data(), count, mix, m_partials.data(), stream());
        std::vector<double> partials(static_cast<size_t>(blocks));
        cudaCheck(cudaMemcpyAsync(partials.data(), m_partials.data(), partials.size() * sizeof(double), cudaMemcpyDeviceToHost, stream()), "KS");
        sync();
        for (double d : partials) out.ksStatistic = std::max(out.ksStatistic, d);
        return out;
    }

    void keepSnapshot() override {
        cudaCheck(cudaMemcpyAsync(m_snapshotX.data(), m_x.data(), size_t(m_n) * sizeof(Vec3<Real>), cudaMemcpyDeviceToDevice, stream()), "snapshot");
        cudaCheck(cudaMemcpyAsync(m_snapshotV.data(), m_v.data(), size_t(m_n) * sizeof(Vec3<Real>), cudaMemcpyDeviceToDevice, stream()), "snapshot");
    }

    ParticleState snapshot() const override { return download(m_snapshotX, m_snapshotV); }

    int64_t computeForcesOnly() override {
        gpu::launchForces(forceArgs(m_x.data(), scratchAcceleration()), stream());
        sync();
        return m_n * (m_n - 1);
    }

    void writeInstances(float* deviceInstances, bool keyIsSpeed) override {
        gpu::launchFillInstances(arrays(), m_radius.data(), keyIsSpeed, deviceInstances, stream());
        sync();
    }

private:
    cudaStream_t stream() const { return m_partition.primary().stream; }

    // Force launches bracketed by events, read once the step has finished (no extra syncs).
    void launchTimedForces(const gpu::ForceArgs<Real>& args) {
        if (m_forceEvents + 2 > m_timingEvents.size()) {
            cudaEvent_t e[2];
            for (cudaEvent_t& ev : e) cudaCheck(cudaEventCreate(&ev), "cudaEventCreate");
            m_timingEvents.push_back(e[0]);
            m_timingEvents.push_back(e[1]);
        }
        cudaCheck(cudaEventRecord(m_timingEvents[m_forceEvents], stream()), "event");
        gpu::launchForces(args, stream());
        cudaCheck(cudaEventRecord(m_timingEvents[m_forceEvents + 1], stream()), "event");
        m_forceEvents += 2;
    }

    void timePhases(StepReport& report) {
        cudaCheck(cudaEventSynchronize(m_phase[2]), "event");
        float ms = 0;
        double forces = 0;
        for (size_t k = 0; k < m_forceEvents; k += 2) {
            cudaEventElapsedTime(&ms, m_timingEvents[k], m_timingEvents[k + 1]);
            forces += ms;
        }
        float integrate = 0, collide = 0;
        cudaEventElapsedTime(&integrate, m_phase[0], m_phase[1]);
        cudaEventElapsedTime(&collide, m_phase[1], m_phase[2]);
        report.secondsForces = 1e-3 * forces;
        report.secondsIntegrate = 1e-3 * (double(integrate) - forces);
        report.secondsCollide = 1e-3 * double(collide);
    }
    void sync() const { m_partition.synchronize(); }

    gpu::ParticleArrays<Real> arrays() { return {m_x.data(), m_v.data(), m_species.data(), m_n}; }
    gpu::SpeciesTable<Real> table() const {
        return {m_pairs.data(), m_mass.data(), m_invMass.data(), m_radius.data(), int(m_params.species.size())};
    }
    gpu::ForceArgs<Real> forceArgs(const Vec3<Real>* x, Vec3<Real>* out) {
        const DeviceSlice& slice = m_partition.primary();
        return {x,   m_species.data(), m_n,     slice.begin, slice.end, table(), m_gravity, m_anyPairForce, m_params.interaction.cutoff > 0,
                out, nullptr, m_forceScratch.data(), m_forceScratch.size()};
    }
    Vec3<Real>* scratchAcceleration() {
        m_scratch.resize(size_t(m_n));
        return m_scratch.data();
    }

    ParticleState download(const DeviceBuffer<Vec3<Real>>& xd, const DeviceBuffer<Vec3<Real>>& vd) const {
        sync();
        std::vector<Vec3<Real>> x(static_cast<size_t>(m_n)), v(static_cast<size_t>(m_n));
        xd.download(x.data(), x.size());
        vd.download(v.data(), v.size());
        ParticleState out;
        out.resize(size_t(m_n));
        for (size_t i = 0; i < size_t(m_n); ++i) {
            out.position[i] = vec3Cast<double>(x[i]);
            out.velocity[i] = vec3Cast<double>(v[i]);
            out.species[i] = m_hostSpecies[i];
        }
        return out;
    }

    // Sums of `rows` rows of m_rows (each n long), block partials added on the host in order.
    std::vector<double> sumRows(int rows) {
        const int blocks = std::max(gpu::blockSumBlocks(m_n), 1);
        m_partials.resize(size_t(rows) * size_t(blocks));
        gpu::launchBlockSums(m_rows.data(), rows, m_n, m_partials.data(), stream());
        std::vector<double> partials(size_t(rows) * size_t(blocks));
        cudaCheck(cudaMemcpyAsync(partials.data(), m_partials.data(), partials.size() * sizeof(double), cudaMemcpyDeviceToHost, stream()), "sums");
        sync();
        std::vector<double> sums(size_t(rows), 0.0);
        for (int r = 0; r < rows; ++r)
            for (int b = 0; b < blocks; ++b) sums[size_t(r)] += partials[size_t(r) * size_t(blocks) + size_t(b)];
        return sums;
    }

public:
    // ---- hooks of integrateStep (src/core/step_driver.h) ----
    void rkStep(double dtStep, int stages) {
        const Real dt = Real(dtStep);
        const size_t n = size_t(m_n);
        m_kx.resize(size_t(m_tableau.stages) * n);
        m_kv.resize(size_t(m_tableau.stages) * n);
        gpu::StageArgs<Real> a{m_x.data(), m_v.data(), m_kx.data(), m_kv.data(), m_xStage.data(), m_vStage.data(), m_n, 0, 0, dt,
                               m_deviceTableau.data()};
        for (int s = 0; s < stages; ++s) {
            a.stage = s;
            a.count = s;
            gpu::launchStage(a, stream());
            launchTimedForces(forceArgs(m_xStage.data(), m_kv.data() + size_t(s) * n));
        }
        a.stage = -1;
        a.count = stages;
        gpu::launchStage(a, stream());
    }

    double embeddedError(double dt, double tolerance) {
        m_rows.resize(size_t(m_n));
        const gpu::StageArgs<Real> a{m_x.data(), m_v.data(), m_kx.data(), m_kv.data(), m_xStage.data(), m_vStage.data(), m_n, -1,
                                     m_tableau.stages, Real(dt), m_deviceTableau.data()};
        gpu::launchErrorNorm(a, tolerance, m_rows.data(), stream());
        return std::sqrt(sumRows(1)[0] / double(6 * std::max<int64_t>(m_n, 1)));
    }

    void acceptStage() {
        std::swap(m_x, m_xStage);
        std::swap(m_v, m_vStage);
    }

    void verletStep(double dtStep) {
        const Real dt = Real(dtStep);
        if (!m_accelerationValid) launchTimedForces(forceArgs(m_x.data(), m_acceleration.data()));
        gpu::launchVerletKickDrift(m_x.data(), m_v.data(), m_acceleration.data(), m_n, dt, stream());
        launchTimedForces(forceArgs(m_x.data(), m_acceleration.data()));
        gpu::launchVerletKick(m_v.data(), m_acceleration.data(), m_n, dt, stream());
        m_accelerationValid = true;
    }

private:
    // Rebuilds the contact cell list from the current positions (cell_list.h: the one rule, cells at
    // least the largest contact distance wide) and returns its view for the collision kernels.
    CellListView buildGrid(cudaStream_t s) {
        gpu::CellListArgs<Real> g{};
        g.x = m_x.data();
        g.n = m_n;
        g.geometry = cellGeometry(vec3Cast<double>(m_box), m_n, 2.0 * m_maxRadius);
        m_cellKeys.resize(size_t(m_n));
        m_sortedCellKeys.resize(size_t(m_n));
        m_cellIndices.resize(size_t(m_n));
        m_sorted.resize(size_t(m_n));
        m_cellStart.resize(size_t(g.geometry.cellCount()) + 1);
        const size_t scratch = gpu::cellListScratchBytes(m_n);
        m_cellScratch.resize(scratch);
        g.cellStart = m_cellStart.data();
        g.sorted = m_sorted.data();
        g.keys = m_cellKeys.data();
        g.sortedKeys = m_sortedCellKeys.data();
        g.indices = m_cellIndices.data();
        g.scratch = m_cellScratch.data();
        g.scratchBytes = scratch;
        gpu::launchBuildCellList(g, s);
        return g.view();
    }

    void resolveCollisions(StepReport& report) {
        const size_t n = size_t(m_n);
        m_events.resize(n);
        m_active.resize(n);
        m_hasContactAcceleration.resize(n);
        m_needList.resize(n);
        m_loss.resize(n);
        cudaStream_t s = stream();
        cudaCheck(cudaMemsetAsync(m_active.data(), 1, n, s), "memset");
        cudaCheck(cudaMemsetAsync(m_hasContactAcceleration.data(), 0, n, s), "memset");
        cudaCheck(cudaMemsetAsync(m_loss.data(), 0, n * sizeof(double), s), "memset");
        cudaCheck(cudaMemsetAsync(m_kindCounts.data(), 0, 3 * sizeof(unsigned long long), s), "memset");
        gpu::CollisionArgs<Real> a{};
        a.p = arrays();
        a.table = table();
        a.box = m_box;
        a.events = m_events.data();
        a.active = m_active.data();
        a.contactAcceleration = m_contactAcceleration.data();
        a.hasContactAcceleration = m_hasContactAcceleration.data();
        a.needList = m_needList.data();
        a.counters = m_counters.data();
        a.kindCounts = m_kindCounts.data();
        a.loss = m_loss.data();
        a.restitution = Real(m_params.interaction.restitution);
        a.wallRestitution = Real(m_params.box.wallRestitution);
        a.elasticBelow = Real(m_params.interaction.elasticBelowSpeed);
        const gpu::ForceArgs<Real> forces = forceArgs(m_x.data(), nullptr);
        bool done = false;
        for (int round = 0; round < m_params.interaction.maxCollisionRounds && !done; ++round) {
            a.grid = buildGrid(s);
            cudaCheck(cudaMemsetAsync(m_counters.data(), 0, 2 * sizeof(unsigned int), s), "memset");
            gpu::launchFindEvents(a, s);
            unsigned int need = 0;
            cudaCheck(cudaMemcpyAsync(&need, m_counters.data(), sizeof need, cudaMemcpyDeviceToHost, s), "events");
            sync();
            gpu::launchContactAccelerations(a, forces, int(need), s);
            gpu::launchResolve(a, s);
            gpu::launchUpdateActive(a, s);
            unsigned int any = 0;
            cudaCheck(cudaMemcpyAsync(&any, m_counters.data() + 1, sizeof any, cudaMemcpyDeviceToHost, s), "events");
            sync();
            report.rounds = round + 1;
            done = any == 0;
        }
        if (!done) {
            // The cap was reached; look once more with every particle active.
            a.grid = buildGrid(s);
            cudaCheck(cudaMemsetAsync(m_active.data(), 1, n, s), "memset");
            cudaCheck(cudaMemsetAsync(m_counters.data(), 0, 2 * sizeof(unsigned int), s), "memset");
            cudaCheck(cudaMemsetAsync(m_hasContactAcceleration.data(), 1, n, s), "memset");  // find only, list nothing
            gpu::launchFindEvents(a, s);
            gpu::launchUpdateActive(a, s);
            unsigned int any = 0;
            cudaCheck(cudaMemcpyAsync(&any, m_counters.data() + 1, sizeof any, cudaMemcpyDeviceToHost, s), "events");
            sync();
            report.roundCapHit = any != 0;
        }
        unsigned long long kinds[3];
        cudaCheck(cudaMemcpyAsync(kinds, m_kindCounts.data(), sizeof kinds, cudaMemcpyDeviceToHost, s), "counts");
        sync();
        report.pairCollisions = int64_t(kinds[0]);
        report.wallCollisions = int64_t(kinds[1]);
        report.positionalFixes = int64_t(kinds[2]);
        if (kinds[0] + kinds[1] + kinds[2] > 0) {
            m_rows.resize(n);
            cudaCheck(cudaMemcpyAsync(m_rows.data(), m_loss.data(), n * sizeof(double), cudaMemcpyDeviceToDevice, s), "loss");
            report.dissipated = sumRows(1)[0];
        }
    }

    int m_device;
    DevicePartition m_partition;
    StepParameters m_params;
    ButcherTableau m_tableau;
    bool m_anyPairForce = true;
    double m_maxRadius = 0;
    Vec3<Real> m_gravity{0, 0, 0}, m_box{1, 1, 1};
    double m_dtNext = 0;
    int64_t m_n = 0;
    bool m_accelerationValid = false;
    std::vector<int32_t> m_hostSpecies;
    cudaEvent_t m_phase[3] = {};  // step start, integrated, collided
    std::vector<cudaEvent_t> m_timingEvents;
    size_t m_forceEvents = 0;

    DeviceBuffer<PairCoefficients<Real>> m_pairs;
    DeviceBuffer<ButcherTableau> m_deviceTableau;
    DeviceBuffer<Real> m_mass, m_invMass, m_radius;
    DeviceBuffer<Vec3<Real>> m_x, m_v, m_acceleration, m_scratch, m_xStage, m_vStage, m_kx, m_kv, m_contactAcceleration;
    DeviceBuffer<Vec3<Real>> m_snapshotX, m_snapshotV;
    DeviceBuffer<int32_t> m_species, m_cellIndices, m_sorted, m_cellStart, m_needList;
    DeviceBuffer<uint32_t> m_cellKeys, m_sortedCellKeys;
    DeviceBuffer<unsigned char> m_cellScratch, m_sortScratch, m_forceScratch;
    DeviceBuffer<CollisionEvent> m_events;
    DeviceBuffer<char> m_active, m_hasContactAcceleration;
    DeviceBuffer<unsigned int> m_counters;
    DeviceBuffer<unsigned long long> m_kindCounts, m_healthCounts, m_histogram;
    DeviceBuffer<long long> m_healthExamples;
    DeviceBuffer<double> m_loss, m_rows, m_partials, m_pairEnergy, m_speeds, m_sortedSpeeds;
};

}  // namespace

std::unique_ptr<Backend> makeCudaBackend(const CudaBackendOptions& options) {
    if (cudaDeviceCount() == 0) throw DeviceError("no CUDA device found (no NVIDIA driver or no GPU); use --backend cpu");
    cudaCheck(cudaSetDevice(options.device), "cudaSetDevice");
    if (options.precision == Precision::Fp32) return std::make_unique<CudaBackendImpl<float>>(options);
    return std::make_unique<CudaBackendImpl<double>>(options);
}

}  // namespace corebox
