#include "instance_feed.h"

#include <cstdio>

#include "errors.h"
#include "particle_renderer.h"
#if COREBOX_WITH_CUDA
#include "gl_buffer_interop.h"
#endif

namespace corebox {

#if !COREBOX_WITH_CUDA
class CudaGlInterop {};
#endif

InstanceFeed::InstanceFeed(Simulation& sim, ParticleRenderer& renderer, ColorMode mode)
    : m_sim(sim), m_renderer(renderer), m_mode(mode), m_description("copy path (instances uploaded each frame)") {
#if COREBOX_WITH_CUDA
    const int device = sim.backend().interopDevice();
    if (device >= 0) {
        m_renderer.reserve(size_t(sim.particleCount()));
        try {
            m_interop = std::make_unique<CudaGlInterop>(m_renderer.instanceBuffer(), device);
            m_description = "CUDA-GL interop on CUDA device " + std::to_string(device);
        } catch (const DeviceError& e) {
            std::fprintf(stderr, "[corebox] warning: no CUDA-GL interop: %s; falling back to the copy path\n", e.what());
        }
    }
#endif
}

InstanceFeed::~InstanceFeed() = default;

void InstanceFeed::update() {
    InstanceTarget target;
    target.key = m_mode;
#if COREBOX_WITH_CUDA
    if (m_interop) {
        const CudaGlInterop::Mapping mapping(*m_interop);
        target.memory = InstanceTarget::Memory::Device;
        target.instances = mapping.instances();
        m_sim.backend().writeInstances(target);
        m_renderer.setInstanceCount(size_t(m_sim.particleCount()));
        return;
    }
#endif
    m_instances.resize(size_t(m_sim.particleCount()));
    target.instances = m_instances.data();
    m_sim.backend().writeInstances(target);
    m_renderer.upload(m_instances.data(), m_instances.size());
}

}  // namespace corebox
