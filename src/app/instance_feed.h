// Fills the renderer's particle buffer from the simulation each frame: through CUDA-GL interop when
// the CUDA backend and the GL context share a GPU (no copy through the host), else by downloading
// the state and uploading it (the copy path, used by the CPU backend and as the fallback).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "particle_view.h"
#include "simulation.h"

namespace corebox {

class ParticleRenderer;
class CudaGlInterop;

// The CUDA device the GL context should run on for interop with this backend, or -1.
int interopDeviceFor(Backend& backend);

class InstanceFeed {
public:
    // Tries interop when the backend is CUDA; on a device mismatch logs why and uses the copy path.
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
