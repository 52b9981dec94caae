// The CUDA backend's collision rounds: a uniform grid rebuilt each round, every particle's earliest
// event (kernels/collision_kernels.cu), end-of-step accelerations of the particles about to be
// resolved, and the resolution of the mutual-earliest matching. One host read-back per round (the
// counts of findEvents); everything else stays on the stream.
#include <algorithm>
#include <cmath>

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
    a.restitution = Real(m_model.restitution);
    a.wallRestitution = Real(m_model.wallRestitution);
    a.elasticBelow = Real(m_model.elasticBelowSpeed);
    // The grid: cells at least the largest contact distance wide, at most ~2 cells per particle.
    gpu::GridArgs<Real>& g = a.grid;
    g.x = m_x.data();
    g.n = m_n;
    const double reach = 2.0 * m_model.maxRadius();
    const double volume = double(m_box.x) * double(m_box.y) * double(m_box.z);
    const double cell = std::max(reach, std::cbrt(volume / double(std::max<int64_t>(2 * m_n, 1))));
    int cells = 1;
    for (int axis = 0; axis < 3; ++axis) {
        g.dims[axis] = std::max(1, int(double(m_box[axis]) / cell));
        g.inverseCell[axis] = Real(double(g.dims[axis]) / double(m_box[axis]));
        cells *= g.dims[axis];
    }
    m_cellOf.resize(size_t(m_n));
    m_sorted.resize(size_t(m_n));
    m_cellStart.resize(size_t(cells) + 1);
    m_cellFill.resize(size_t(cells) + 1);
    const size_t scratch = gpu::gridScanScratchBytes(cells);
    m_scanScratch.resize(scratch);
    g.cellOf = m_cellOf.data();
    g.cellStart = m_cellStart.data();
    g.cellFill = m_cellFill.data();
    g.sorted = m_sorted.data();
    g.scanScratch = m_scanScratch.data();
    g.scanScratchBytes = scratch;
    return a;
}

template <class Real>
void CudaDevice<Real>::beginCollisions() {
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
}

template <class Real>
int64_t CudaDevice<Real>::findEvents(EventScope scope) {
    cudaStream_t s = stream();
    const gpu::CollisionArgs<Real> a = collisionArgs();
    gpu::launchBuildGrid(a.grid, s);
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
    t.positionalFixes = int64_t(kinds[2]);
    if (t.total() > 0) {
        m_rows.resize(size_t(m_n));
        cudaCheck(cudaMemcpyAsync(m_rows.data(), m_loss.data(), size_t(m_n) * sizeof(double), cudaMemcpyDeviceToDevice, stream()), "loss");
        t.dissipated = sumRows(1)[0];
    }
    return t;
}

template class CudaDevice<float>;
template class CudaDevice<double>;

}  // namespace corebox
