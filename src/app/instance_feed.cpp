#include "instance_feed.h"

#include <cstdio>

#include "errors.h"
#include "particle_renderer.h"
#include "scene_view.h"
#if COREBOX_WITH_CUDA
#include "cuda_backend.h"
#include "gl_buffer_interop.h"
#endif

namespace corebox {

#if !COREBOX_WITH_CUDA
class CudaGlInterop {};
#endif

int interopDeviceFor([[maybe_unused]] Backend& backend) {
#if COREBOX_WITH_CUDA
    if (auto* source = dynamic_cast<CudaParticleSource*>(&backend)) return source->device();
#endif
    return -1;
}

InstanceFeed::InstanceFeed(Simulation& sim, ParticleRenderer& renderer, ColorMode mode)
    : m_sim(sim), m_renderer(renderer), m_mode(mode), m_description("copy path (state uploaded each frame)") {
#if COREBOX_WITH_CUDA
    if (auto* source = dynamic_cast<CudaParticleSource*>(&sim.backend())) {
        m_renderer.reserve(size_t(sim.particleCount()));
        try {
            m_interop = std::make_unique<CudaGlInterop>(m_renderer.instanceBuffer(), source->device());
            m_description = "CUDA-GL interop on CUDA device " + std::to_string(source->device());
        } catch (const DeviceError& e) {
            std::fprintf(stderr, "[corebox] warning: no CUDA-GL interop: %s; falling back to the copy path\n", e.what());
        }
    }
#endif
}

InstanceFeed::~InstanceFeed() = default;

void InstanceFeed::update() {
#if COREBOX_WITH_CUDA
    if (m_interop) {
        auto* source = dynamic_cast<CudaParticleSource*>(&m_sim.backend());
        m_interop->fill(*source, m_mode == ColorMode::Speed);
        m_renderer.setInstanceCount(size_t(m_sim.particleCount()));
        return;
    }
#endif
    buildInstances(m_sim.state(), m_sim.scene(), m_mode, m_instances);
    m_renderer.upload(m_instances.data(), m_instances.size());
}

}  // namespace corebox
