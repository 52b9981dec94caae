// Fills the renderer's particle buffer from the simulation each frame through the backend's
// writeInstances: straight into the mapped GL buffer (CUDA-GL interop) when the backend's
// interopDevice() is the GPU the GL context runs on, else into host memory that is then uploaded
// (the copy path: the CPU backend, another GPU, or a context without CUDA).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "render_style.h"
#include "simulation.h"

namespace corebox {

class ParticleRenderer;
class CudaGlInterop;

class InstanceFeed {
public:
    // Tries interop when the backend has an interop device; on a device mismatch logs why and uses
    // the copy path.
    InstanceFeed(Simulation& sim, ParticleRenderer& renderer, ColorMode mode);
    ~InstanceFeed();

    void update();
    bool usesInterop() const { return m_interop != nullptr; }
    const std::string& description() const { return m_description; }

private:
    Simulation& m_sim;
    ParticleRenderer& m_renderer;
    ColorMode m_mode;
    std::unique_ptr<CudaGlInterop> m_interop;
    std::vector<ParticleInstance> m_instances;
    std::string m_description;
};

}  // namespace corebox
