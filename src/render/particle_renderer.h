// OpenGL 4.5 core renderer (through libepoxy): particles as lit, ray-traced sphere impostors of
// their true radius (instanced quads; each fragment's true depth, or with RenderStyle::exactDepth false
// each sphere's nearest point's), the box as edges, and a legend (species
// swatches or a speed colour bar with its range). It owns its GL objects, including the particle
// instance buffer; the CPU path uploads into it, the CUDA path (src/cuda) registers it for interop
// and writes into it directly. Needs a current GL 4.5 context for its whole life.
#pragma once

#include <epoxy/gl.h>

#include <array>
#include <cstddef>
#include <cstdint>

#include "orbit_camera.h"
#include "render_style.h"

namespace corebox {

class ParticleRenderer {
public:
    ParticleRenderer();  // throws RenderError when a shader does not build (the flat-depth variant: render())
    ~ParticleRenderer();
    ParticleRenderer(const ParticleRenderer&) = delete;
    ParticleRenderer& operator=(const ParticleRenderer&) = delete;

    // Capacity for n instances. Reallocating makes a new buffer object: bufferGeneration() changes,
    // and an interop registration of the old buffer must be renewed.
    void reserve(size_t n);
    GLuint instanceBuffer() const { return m_instanceBuffer; }
    uint64_t bufferGeneration() const { return m_bufferGeneration; }

    // CPU path: copy n instances into the buffer (reserving as needed).
    void upload(const ParticleInstance* instances, size_t n);
    // Interop path: the buffer was filled elsewhere with n instances.
    void setInstanceCount(size_t n) { m_count = n; }

    // Draws into the currently bound framebuffer of the given size.
    void render(const OrbitCamera& camera, const std::array<float, 3>& boxSize, const RenderStyle& style, int width,
                int height);
    // Pixels the legend takes at the bottom of a frame `height` tall (the speed key; 0 in species
    // mode, whose swatches sit at the top left): overlays keep clear of them.
    static float legendBottomHeight(ColorMode mode, int height);

private:
    void drawBox(const glm::mat4& viewProjection, const std::array<float, 3>& boxSize, const RenderStyle& style);
    void drawLegend(const RenderStyle& style, int width, int height);
    static float legendScale(int height);
    GLuint sphereProgram(bool exactDepth);

    GLuint m_sphereProgram = 0, m_lineProgram = 0, m_overlayProgram = 0;
    GLuint m_flatSphereProgram = 0;  // RenderStyle::exactDepth false; built when first drawn
    GLuint m_sphereVao = 0, m_instanceBuffer = 0;
    GLuint m_lineVao = 0, m_lineBuffer = 0;
    GLuint m_overlayVao = 0, m_overlayBuffer = 0;
    size_t m_capacity = 0, m_count = 0;
    uint64_t m_bufferGeneration = 0;
};

}  // namespace corebox
