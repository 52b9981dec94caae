// The CUDA backend's class, shared by the files that implement it: cuda_backend.cpp (model, state,
// reductions, timing, output), cuda_integration.cpp (forces, RK stages, Verlet) and
// cuda_collisions.cpp (the collision rounds' event search and resolution). Internal to src/cuda.
#pragma once

#include <vector>

#include "backend.h"
#include "cuda_backend.h"
#include "cuda_check.h"
#include "device_buffer.h"
#include "device_cell_list.h"
#include "device_partition.h"
#include "gpu_launch.h"

namespace corebox {

template <class Real>
class CudaDevice final : public Backend {
public:
    explicit CudaDevice(const CudaBackendOptions& options);
    ~CudaDevice() override;

    // ---- identity ----
    std::string name() const override { return "cuda"; }
    std::string deviceName() const override { return cudaDeviceDescription(m_device); }
    Precision precision() const override { return std::is_same<Real, float>::value ? Precision::Fp32 : Precision::Fp64; }
    int interopDevice() const override { return m_device; }

    // ---- model and state (cuda_backend.cpp) ----
    void setModel(const DeviceModel& model) override;
    void setTableau(const ButcherTableau& tableau) override;
    void setState(const ParticleState& state) override;
    ParticleState state() const override { return download(m_x, m_v); }
    void keepSnapshot() override;
    ParticleState snapshot() const override { return download(m_snapshotX, m_snapshotV); }

    // ---- integration (cuda_integration.cpp) ----
    void computeAccelerations() override;
    void kick(double h) override;
    void drift(double dt) override;
    void rkStage(int stage, double dt) override;
    void stageForces(int stage) override;
    void rkSolution(int stages, double dt) override;
    double rkErrorNorm(double dt, double tolerance) override;
    void acceptStage() override;

    // ---- collision rounds (cuda_collisions.cpp) ----
    void beginCollisions(const ImpactWindow<double>& window) override;
    int64_t findEvents(EventScope scope) override;
    void applyEvents() override;
    CollisionTally collisionTally() override;
    int64_t listContacts(const RestingContact<double>& resting) override;
    ContactResidual<double> relaxContacts(int sweeps) override;
    double contactLiftWork() override;
    ImpulseSums contactImpulses() override;

    // ---- reductions, timing, output (cuda_backend.cpp) ----
    double kineticEnergy() override;
    void scaleVelocities(double alpha) override;
    EnergySums energies() override;
    double pairVirial() override;  // cuda_pressure.cpp
    HealthReport health() override;
    void markPhase(StepPhase phase) override;
    PhaseSeconds phaseSeconds() override;
    void writeInstances(const InstanceTarget& target) override;
    void finish() override { sync(); }

private:
    cudaStream_t stream() const { return m_partition.primary().stream; }
    void sync() const { m_partition.synchronize(); }
    gpu::ParticleArrays<Real> arrays() { return {m_x.data(), m_v.data(), m_species.data(), m_n}; }
    gpu::SpeciesTable<Real> table() const { return {m_pairs.data(), m_mass.data(), m_invMass.data(), m_radius.data(), m_speciesCount}; }
    gpu::ForceArgs<Real> forceArgs(const Vec3<Real>* x, Vec3<Real>* out);
    // Force launches bracketed by timing events, read once the step has finished (no extra syncs).
    void launchTimedForces(const gpu::ForceArgs<Real>& args);
    ParticleState download(const DeviceBuffer<Vec3<Real>>& x, const DeviceBuffer<Vec3<Real>>& v) const;
    // Sums of `rows` rows of m_rows (each n long); block partials are added on the host in order.
    std::vector<double> sumRows(int rows);
    template <class T>
    T readBack(const DeviceBuffer<T>& buffer, size_t offset = 0) {  // one value, after a sync
        T value{};
        cudaCheck(cudaMemcpyAsync(&value, buffer.data() + offset, sizeof(T), cudaMemcpyDeviceToHost, stream()), "read-back");
        sync();
        return value;
    }
    // Sums the kImpulseRows rows of `rows` (impulse_sums.h) in a fixed order (cuda_pressure.cpp).
    ImpulseSums sumImpulseRows(const DeviceBuffer<double>& rows);
    gpu::CollisionArgs<Real> collisionArgs();
    gpu::ContactArgs<Real> contactArgs();

    int m_device;
    DevicePartition m_partition;
    DeviceModel m_model;
    ButcherTableau m_tableau{};
    int m_speciesCount = 0;
    Vec3<Real> m_gravity{0, 0, 0}, m_box{1, 1, 1};
    int64_t m_n = 0;
    std::vector<int32_t> m_hostSpecies;

    cudaEvent_t m_phase[3] = {};  // Integrate, Collide, Done marks
    std::vector<cudaEvent_t> m_timingEvents;
    size_t m_forceEvents = 0;
    bool m_timingForces = false;  // between the Integrate and Collide marks

    DeviceBuffer<PairCoefficients<Real>> m_pairs;
    DeviceBuffer<ButcherTableau> m_deviceTableau;
    DeviceBuffer<Real> m_mass, m_invMass, m_radius;
    DeviceBuffer<Vec3<Real>> m_x, m_v, m_acceleration, m_scratch, m_xStage, m_vStage, m_kx, m_kv, m_contactAcceleration;
    DeviceBuffer<Vec3<Real>> m_snapshotX, m_snapshotV;
    DeviceBuffer<int32_t> m_species, m_needList;
    DeviceCellList<Real> m_contactCells;
    CellListView m_cellList{};  // of the last findEvents or listContacts
    ImpactWindow<Real> m_window{0, 0};
    RestingContact<Real> m_resting{0, 0};
    DeviceBuffer<int64_t> m_contactStart, m_contactPartner;
    DeviceBuffer<Vec3<Real>> m_xListed, m_dv, m_dx;
    DeviceBuffer<unsigned long long> m_residual;  // [approach speed, overlap], double bits
    DeviceBuffer<unsigned char> m_contactScanScratch;
    DeviceBuffer<unsigned char> m_forceScratch;
    DeviceBuffer<CollisionEvent> m_events;
    DeviceBuffer<char> m_active, m_hasContactAcceleration;
    DeviceBuffer<unsigned int> m_counters;  // [0] particles needing a contact acceleration, [1] particles with an event
    unsigned int m_needCount = 0;           // counters[0] of the last findEvents
    DeviceBuffer<unsigned long long> m_kindCounts, m_healthCounts;
    DeviceBuffer<long long> m_healthExamples;
    DeviceBuffer<double> m_loss, m_rows, m_partials, m_pairEnergy;
    DeviceBuffer<double> m_impactImpulses, m_contactImpulses;  // kImpulseRows x n each (impulse_sums.h)
    DeviceBuffer<ParticleInstance> m_instances;  // staging for host instance targets
};

}  // namespace corebox
