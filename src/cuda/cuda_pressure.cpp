// The CUDA backend's sums for the pressure observables (src/core/pressure.h): the pair-force virial
// (kernels/pressure_kernels.cu) and the impulse rows the collision stage fills per particle
// (impulse_sums.h). Only the sums cross to the host, added in block order: deterministic.
#include "cuda_device.h"

namespace corebox {

template <class Real>
ImpulseSums CudaDevice<Real>::sumImpulseRows(const DeviceBuffer<double>& rows) {
    const int blocks = queuePartialSums(rows.data(), kImpulseRows);
    sync();
    return impulseSumsOf(hostPartialSums(kImpulseRows, blocks));
}

template <class Real>
ImpulseSums CudaDevice<Real>::impulseSumsOf(const std::vector<double>& sums) {
    ImpulseSums out;
    for (int k = 0; k < kWallCount; ++k) {
        out.wall[k] = sums[size_t(k)];
        out.wallCentre[k] = sums[size_t(kWallCount + k)];
    }
    out.pairVirial = sums[size_t(kPairVirialRow)];
    return out;
}

template <class Real>
CollisionTally CudaDevice<Real>::tallyOf(const unsigned long long kindCounts[2], const std::vector<double>& sums) {
    CollisionTally t;
    t.pairCollisions = int64_t(kindCounts[0]);
    t.wallCollisions = int64_t(kindCounts[1]);
    if (t.total() > 0) {
        t.dissipated = sums[size_t(kImpulseRows)];
        t.impulses = impulseSumsOf(sums);
    }
    return t;
}

template <class Real>
double CudaDevice<Real>::pairVirial() {
    if (!m_model.anyPairForce || m_n == 0) return 0;
    gatherToHome();
    m_rows.resize(size_t(m_n));
    if (useLists() && gpuCount() == 1) {  // one GPU: its lists cover every row
        gpu::ForceArgs<Real> f = homeForceArgs(home().x.data(), m_scratch.data());
        home().list.update(home().x.data(), m_n, 0, m_n, m_box, m_model.cutoff, m_model.skin, stream());
        home().list.fill(f);
        gpu::launchListVirialRows(f, m_rows.data(), stream());
    } else {
        gpu::launchPairVirialRow(arrays(), table(), m_rows.data(), stream());
    }
    return sumRows(1)[0];
}

template class CudaDevice<float>;
template class CudaDevice<double>;

}  // namespace corebox
