// The CUDA backend's integration operations: force passes (timed by stream events), Runge-Kutta
// stages and Verlet's kick and drift, each a launch of kernels/force_kernels.cu or
// kernels/integrate_kernels.cu on the backend's stream.
#include "cuda_device.h"

namespace corebox {

template <class Real>
gpu::ForceArgs<Real> CudaDevice<Real>::forceArgs(const Vec3<Real>* x, Vec3<Real>* out) {
    const DeviceSlice& slice = m_partition.primary();
    return {x,   m_species.data(), m_n,     slice.begin, slice.end, table(), m_gravity, m_model.anyPairForce, m_model.hasCutoff,
            out, nullptr,          m_forceScratch.data(), m_forceScratch.size()};
}

template <class Real>
void CudaDevice<Real>::launchTimedForces(const gpu::ForceArgs<Real>& args) {
    if (!m_timingForces) {  // outside a step (energies, benchmarks): nothing to attribute the time to
        gpu::launchForces(args, stream());
        return;
    }
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

template <class Real>
void CudaDevice<Real>::computeAccelerations() {
    launchTimedForces(forceArgs(m_x.data(), m_acceleration.data()));
}

template <class Real>
void CudaDevice<Real>::kick(double h) {
    gpu::launchVerletKick(m_v.data(), m_acceleration.data(), m_n, Real(h), stream());
}

template <class Real>
void CudaDevice<Real>::drift(double dt) {
    gpu::launchVerletDrift(m_x.data(), m_v.data(), m_n, Real(dt), stream());
}

template <class Real>
void CudaDevice<Real>::rkStage(int stage, double dt) {
    const size_t n = size_t(m_n);
    m_kx.resize(size_t(m_tableau.stages) * n);
    m_kv.resize(size_t(m_tableau.stages) * n);
    const gpu::StageArgs<Real> a{m_x.data(), m_v.data(), m_kx.data(), m_kv.data(), m_xStage.data(), m_vStage.data(), m_n, stage, stage,
                                 Real(dt), m_deviceTableau.data()};
    gpu::launchStage(a, stream());
}

template <class Real>
void CudaDevice<Real>::stageForces(int stage) {
    launchTimedForces(forceArgs(m_xStage.data(), m_kv.data() + size_t(stage) * size_t(m_n)));
}

template <class Real>
void CudaDevice<Real>::rkSolution(int stages, double dt) {
    const gpu::StageArgs<Real> a{m_x.data(), m_v.data(), m_kx.data(), m_kv.data(), m_xStage.data(), m_vStage.data(), m_n, -1, stages,
                                 Real(dt), m_deviceTableau.data()};
    gpu::launchStage(a, stream());
}

template <class Real>
double CudaDevice<Real>::rkErrorNorm(double dt, double tolerance) {
    m_rows.resize(size_t(m_n));
    const gpu::StageArgs<Real> a{m_x.data(), m_v.data(), m_kx.data(), m_kv.data(), m_xStage.data(), m_vStage.data(), m_n, -1,
                                 m_tableau.stages, Real(dt), m_deviceTableau.data()};
    gpu::launchErrorNorm(a, tolerance, m_rows.data(), stream());
    return std::sqrt(sumRows(1)[0] / double(6 * std::max<int64_t>(m_n, 1)));
}

template <class Real>
void CudaDevice<Real>::acceptStage() {
    std::swap(m_x, m_xStage);
    std::swap(m_v, m_vStage);
}

template class CudaDevice<float>;
template class CudaDevice<double>;

}  // namespace corebox
