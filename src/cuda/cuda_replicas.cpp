// The CUDA backend's state movement between GPUs (design note in cuda_device.h): the gather of every
// slice to the home GPU before whole-state work, the scatter of what the home GPU changed back to
// the slices' owners, and the downloads and device views that read the gathered state.
#include "cuda_device.h"
#include "state_conversions.h"

namespace corebox {

template <class Real>
std::vector<std::vector<void*>> CudaDevice<Real>::stateBuffers() const {
    std::vector<void*> x, v;
    for (auto& r : m_replicas) {
        x.push_back(r->x.data());
        v.push_back(r->v.data());
    }
    return {x, v};
}

template <class Real>
void CudaDevice<Real>::gatherToHome() const {
    if (m_homeCurrent) return;
    m_exchange->gather(stateBuffers(), sizeof(Vec3<Real>));
    m_homeCurrent = true;
}

template <class Real>
void CudaDevice<Real>::scatterFromHome() const {
    if (m_slicesCurrent) return;
    m_exchange->scatter(stateBuffers(), sizeof(Vec3<Real>));
    m_slicesCurrent = true;
}

template <class Real>
std::string CudaDevice<Real>::deviceName() const {
    const std::string one = cudaDeviceDescription(home().device);
    if (gpuCount() == 1) return one;
    return std::to_string(gpuCount()) + " x " + one + ", " + exchangeName(m_exchange->method()) + " exchange";
}

template <class Real>
ParticleState CudaDevice<Real>::state() const {
    ParticleState out;
    readState(out);
    return out;
}

template <class Real>
void CudaDevice<Real>::readState(ParticleState& out) const {
    gatherToHome();
    download(home().x, home().v, out);
}

template <class Real>
void CudaDevice<Real>::readPositions(const PositionSink& sink) const {
    gatherToHome();
    const size_t n = size_t(m_n);
    if (n == 0) return;
    Vec3<Real>* x = m_hostStateX.resize(n);
    cudaCheck(cudaMemcpyAsync(x, home().x.data(), n * sizeof(Vec3<Real>), cudaMemcpyDeviceToHost, stream()),
              "positions");
    sync();
    handPositions(x, n, sink, 0);
}

template <class Real>
DeviceState CudaDevice<Real>::deviceState() {
    gatherToHome();  // the home GPU's full-length arrays then hold every slice
    DeviceState view;
    view.device = home().device;
    view.precision = precision();
    view.position = home().x.data();
    view.velocity = home().v.data();
    view.species = home().species.data();
    view.count = m_n;
    view.stream = stream();
    return view;
}

template <class Real>
ParticleState CudaDevice<Real>::snapshot() const {
    takeSnapshot();
    ParticleState out;
    download(m_snapshotX, m_snapshotV, out);
    return out;
}

template class CudaDevice<float>;
template class CudaDevice<double>;

}  // namespace corebox
