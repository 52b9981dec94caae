// The CUDA backend's collision rounds: the cell list rebuilt each round, every particle's earliest
// event (kernels/collision_kernels.cu), end-of-step accelerations of the particles about to be
// resolved, and the resolution of the mutual-earliest matching. One host read-back per round (the
// counts of findEvents); everything else stays on the stream. Impulses for the pressure observables
// (impulse_sums.h) go into per-particle rows, summed in a fixed order when the tally is read.
#include <algorithm>
#include <cmath>
#include <cstring>

#include "cuda_device.h"

namespace corebox {

template <class Real>
gpu::CollisionArgs<Real> CudaDevice<Real>::collisionArgs() {
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
    a.impulses = m_impactImpulses.data();
    a.restitution = Real(m_model.restitution);
    a.wallRestitution = Real(m_model.wallRestitution);
    a.elasticBelow = Real(m_model.elasticBelowSpeed);
    a.window = m_window;
    a.grid = m_cellList;
    return a;
}

template <class Real>
void CudaDevice<Real>::beginCollisions(const ImpactWindow<double>& window) {
    m_window = ImpactWindow<Real>{Real(window.maxRewind), Real(window.restingSpeed)};
    const size_t n = size_t(m_n);
    m_events.resize(n);
    m_active.resize(n);
    m_hasContactAcceleration.resize(n);
    m_needList.resize(n);
    m_loss.resize(n);
    m_impactImpulses.resize(size_t(kImpulseRows) * n);
    cudaStream_t s = stream();
    cudaCheck(cudaMemsetAsync(m_active.data(), 1, n, s), "memset");
    cudaCheck(cudaMemsetAsync(m_hasContactAcceleration.data(), 0, n, s), "memset");
    cudaCheck(cudaMemsetAsync(m_loss.data(), 0, n * sizeof(double), s), "memset");
    cudaCheck(cudaMemsetAsync(m_impactImpulses.data(), 0, size_t(kImpulseRows) * n * sizeof(double), s), "memset");
    cudaCheck(cudaMemsetAsync(m_kindCounts.data(), 0, 3 * sizeof(unsigned long long), s), "memset");
}

template <class Real>
int64_t CudaDevice<Real>::findEvents(EventScope scope) {
    cudaStream_t s = stream();
    // Cells at least the largest contact distance wide (cell_list.h: the one rule).
    m_cellList = m_contactCells.build(m_x.data(), m_n, cellGeometry(vec3Cast<double>(m_box), m_n, 2.0 * m_model.maxRadius()), s);
    const gpu::CollisionArgs<Real> a = collisionArgs();
    if (scope == EventScope::All) cudaCheck(cudaMemsetAsync(m_active.data(), 1, size_t(m_n), s), "memset");
    cudaCheck(cudaMemsetAsync(m_counters.data(), 0, 2 * sizeof(unsigned int), s), "memset");
    gpu::launchFindEvents(a, s);
    unsigned int counts[2] = {0, 0};
    cudaCheck(cudaMemcpyAsync(counts, m_counters.data(), sizeof counts, cudaMemcpyDeviceToHost, s), "events");
    sync();
    m_needCount = counts[0];
    return int64_t(counts[1]);
}

template <class Real>
void CudaDevice<Real>::applyEvents() {
    cudaStream_t s = stream();
    const gpu::CollisionArgs<Real> a = collisionArgs();
    gpu::launchContactAccelerations(a, forceArgs(m_x.data(), nullptr), int(m_needCount), s);
    gpu::launchResolve(a, s);
    gpu::launchUpdateActive(a, s);
}

template <class Real>
CollisionTally CudaDevice<Real>::collisionTally() {
    unsigned long long kinds[3];
    cudaCheck(cudaMemcpyAsync(kinds, m_kindCounts.data(), sizeof kinds, cudaMemcpyDeviceToHost, stream()), "counts");
    sync();
    CollisionTally t;
    t.pairCollisions = int64_t(kinds[0]);
    t.wallCollisions = int64_t(kinds[1]);
    if (t.total() > 0) {
        m_rows.resize(size_t(m_n));
        cudaCheck(cudaMemcpyAsync(m_rows.data(), m_loss.data(), size_t(m_n) * sizeof(double), cudaMemcpyDeviceToDevice, stream()), "loss");
        t.dissipated = sumRows(1)[0];
        t.impulses = sumImpulseRows(m_impactImpulses);
    }
    return t;
}

template <class Real>
gpu::ContactArgs<Real> CudaDevice<Real>::contactArgs() {
    gpu::ContactArgs<Real> a{};
    a.p = arrays();
    a.table = table();
    a.box = m_box;
    a.cells = m_cellList;
    a.contactStart = m_contactStart.data();
    a.partner = m_contactPartner.data();
    a.resting = m_resting;
    a.up = upOf(m_gravity);
    a.dv = m_dv.data();
    a.dx = m_dx.data();
    a.residual = m_residual.data();
    a.impulses = m_contactImpulses.data();
    return a;
}

template <class Real>
int64_t CudaDevice<Real>::listContacts(const RestingContact<double>& resting) {
    cudaStream_t s = stream();
    m_resting = RestingContact<Real>{Real(resting.speed), Real(resting.gap)};
    const double reach = 2.0 * m_model.maxRadius() + resting.gap;  // every listed pair in neighbouring cells
    m_cellList = m_contactCells.build(m_x.data(), m_n, cellGeometry(vec3Cast<double>(m_box), m_n, reach), s);
    m_contactStart.resize(size_t(m_n) + 1);
    m_residual.resize(2);
    for (auto* b : {&m_xListed, &m_dv, &m_dx}) b->resize(size_t(m_n));
    gpu::launchCountContacts(contactArgs(), s);
    const size_t scratch = gpu::contactScanScratchBytes(m_n);
    m_contactScanScratch.resize(scratch);
    gpu::scanContactCounts(m_contactStart.data(), m_n, m_contactScanScratch.data(), scratch, s);
    const int64_t total = readBack(m_contactStart, size_t(m_n));
    if (total == 0) return 0;
    m_contactPartner.resize(size_t(total));
    m_contactImpulses.resize(size_t(kImpulseRows) * size_t(m_n));
    cudaCheck(cudaMemsetAsync(m_contactImpulses.data(), 0, size_t(kImpulseRows) * size_t(m_n) * sizeof(double), s), "memset");
    gpu::launchFillContacts(contactArgs(), s);
    cudaCheck(cudaMemcpyAsync(m_xListed.data(), m_x.data(), size_t(m_n) * sizeof(Vec3<Real>), cudaMemcpyDeviceToDevice, s), "contacts");
    return total;
}

template <class Real>
ContactResidual<double> CudaDevice<Real>::relaxContacts(int sweeps) {
    gpu::launchRelaxContacts(contactArgs(), sweeps, stream());
    unsigned long long bits[2] = {0, 0};
    cudaCheck(cudaMemcpyAsync(bits, m_residual.data(), sizeof bits, cudaMemcpyDeviceToHost, stream()), "contact residual");
    sync();
    ContactResidual<double> r{0, 0};
    std::memcpy(&r.approachSpeed, &bits[0], sizeof(double));
    std::memcpy(&r.overlap, &bits[1], sizeof(double));
    return r;
}

template <class Real>
double CudaDevice<Real>::contactLiftWork() {
    m_rows.resize(size_t(m_n));
    gpu::launchLiftWorkRow(arrays(), table(), m_gravity, m_xListed.data(), m_rows.data(), stream());
    return sumRows(1)[0];
}

template <class Real>
ImpulseSums CudaDevice<Real>::contactImpulses() {
    return sumImpulseRows(m_contactImpulses);
}

template class CudaDevice<float>;
template class CudaDevice<double>;

}  // namespace corebox
