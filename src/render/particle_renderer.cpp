#include "particle_renderer.h"

#include <cstdio>
#include <glm/gtc/type_ptr.hpp>
#include <string>
#include <vector>

#include "gl_program.h"
#include "shader_sources.h"

// stb_easy_font: tiny vector font as quads; its functions are static, so including it here is the
// whole implementation.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#include <stb/stb_easy_font.h>
#pragma GCC diagnostic pop

namespace corebox {
namespace {

struct OverlayVertex {
    float x, y;
    float r, g, b, a;
    float colormapT;  // >= 0: take the colour from the colormap
};

void addQuad(std::vector<OverlayVertex>& out, float x0, float y0, float x1, float y1, const std::array<float, 4>& c,
             float t0 = -1.0f, float t1 = -1.0f) {
    const OverlayVertex v00{x0, y0, c[0], c[1], c[2], c[3], t0}, v10{x1, y0, c[0], c[1], c[2], c[3], t1};
    const OverlayVertex v01{x0, y1, c[0], c[1], c[2], c[3], t0}, v11{x1, y1, c[0], c[1], c[2], c[3], t1};
    out.insert(out.end(), {v00, v10, v11, v00, v11, v01});
}

// Text at pixel (x, y), top-left, scaled up from stb_easy_font's ~7 px glyphs.
void addText(std::vector<OverlayVertex>& out, float x, float y, const std::string& text, float scale,
             const std::array<float, 4>& color) {
    // stb_easy_font stops writing when the buffer is full, and its "~270 bytes per character" is an
    // average: digit-heavy text needs more ("(32768)" lost its last glyphs). Each segment is a quad
    // of 64 bytes; 16 per character is more than any glyph of the font has.
    std::vector<char> buffer(text.size() * 16 * 64 + 64);
    std::string copy = text;
    const int quads = stb_easy_font_print(0, 0, copy.data(), nullptr, buffer.data(), int(buffer.size()));
    const float* v = reinterpret_cast<const float*>(buffer.data());
    for (int q = 0; q < quads; ++q) {
        const float* p = v + q * 16;  // 4 vertices of (x, y, z, rgba-as-float)
        addQuad(out, x + scale * p[0], y + scale * p[1], x + scale * p[8], y + scale * p[9], color);
    }
}

std::string formatValue(float v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.3g", double(v));
    return buf;
}

// viridis.frag before sphere.frag, the order tests/render/validate_shaders.sh links them in (glslang takes
// sphere.frag's redeclared gl_FragDepth layout only after the units without one).
GLuint buildSphereProgram(const char* fragmentText, const char* name) {
    return buildProgram({{GL_VERTEX_SHADER, shaders::sphere_vert, "sphere.vert"},
                         {GL_FRAGMENT_SHADER, shaders::viridis_frag, "viridis.frag"},
                         {GL_FRAGMENT_SHADER, fragmentText, "sphere.frag"}},
                        name);
}

}  // namespace

ParticleRenderer::ParticleRenderer() {
    m_sphereProgram = buildSphereProgram(shaders::sphere_frag, "sphere");
    m_lineProgram = buildProgram({{GL_VERTEX_SHADER, shaders::lines_vert, "lines.vert"},
                                  {GL_FRAGMENT_SHADER, shaders::flat_frag, "flat.frag"}},
                                 "lines");
    m_overlayProgram = buildProgram({{GL_VERTEX_SHADER, shaders::overlay_vert, "overlay.vert"},
                                     {GL_FRAGMENT_SHADER, shaders::overlay_frag, "overlay.frag"},
                                     {GL_FRAGMENT_SHADER, shaders::viridis_frag, "viridis.frag"}},
                                    "overlay");

    glCreateVertexArrays(1, &m_sphereVao);
    glCreateVertexArrays(1, &m_lineVao);
    glCreateBuffers(1, &m_lineBuffer);
    glNamedBufferData(m_lineBuffer, 24 * 3 * sizeof(float), nullptr, GL_DYNAMIC_DRAW);
    glVertexArrayVertexBuffer(m_lineVao, 0, m_lineBuffer, 0, 3 * sizeof(float));
    glEnableVertexArrayAttrib(m_lineVao, 0);
    glVertexArrayAttribFormat(m_lineVao, 0, 3, GL_FLOAT, GL_FALSE, 0);
    glVertexArrayAttribBinding(m_lineVao, 0, 0);

    glCreateVertexArrays(1, &m_overlayVao);
    glCreateBuffers(1, &m_overlayBuffer);
    glVertexArrayVertexBuffer(m_overlayVao, 0, m_overlayBuffer, 0, sizeof(OverlayVertex));
    const GLuint sizes[3] = {2, 4, 1};
    const GLuint offsets[3] = {0, 2 * sizeof(float), 6 * sizeof(float)};
    for (GLuint a = 0; a < 3; ++a) {
        glEnableVertexArrayAttrib(m_overlayVao, a);
        glVertexArrayAttribFormat(m_overlayVao, a, GLint(sizes[a]), GL_FLOAT, GL_FALSE, offsets[a]);
        glVertexArrayAttribBinding(m_overlayVao, a, 0);
    }
    reserve(1024);
}

ParticleRenderer::~ParticleRenderer() {
    glDeleteProgram(m_sphereProgram);
    glDeleteProgram(m_flatSphereProgram);  // 0 if never built: ignored
    glDeleteProgram(m_lineProgram);
    glDeleteProgram(m_overlayProgram);
    const GLuint buffers[3] = {m_instanceBuffer, m_lineBuffer, m_overlayBuffer};
    glDeleteBuffers(3, buffers);
    const GLuint arrays[3] = {m_sphereVao, m_lineVao, m_overlayVao};
    glDeleteVertexArrays(3, arrays);
}

void ParticleRenderer::reserve(size_t n) {
    if (n <= m_capacity && m_instanceBuffer != 0) return;
    const size_t capacity = std::max(n, m_capacity + m_capacity / 2);
    if (m_instanceBuffer != 0) glDeleteBuffers(1, &m_instanceBuffer);
    glCreateBuffers(1, &m_instanceBuffer);
    glNamedBufferData(m_instanceBuffer, GLsizeiptr(capacity * sizeof(ParticleInstance)), nullptr, GL_DYNAMIC_DRAW);
    // One instance per particle: attribute 0 = (x, y, z, radius), attribute 1 = colour key.
    glVertexArrayVertexBuffer(m_sphereVao, 0, m_instanceBuffer, 0, sizeof(ParticleInstance));
    glVertexArrayBindingDivisor(m_sphereVao, 0, 1);
    glEnableVertexArrayAttrib(m_sphereVao, 0);
    glVertexArrayAttribFormat(m_sphereVao, 0, 4, GL_FLOAT, GL_FALSE, 0);
    glVertexArrayAttribBinding(m_sphereVao, 0, 0);
    glEnableVertexArrayAttrib(m_sphereVao, 1);
    glVertexArrayAttribFormat(m_sphereVao, 1, 1, GL_FLOAT, GL_FALSE, 4 * sizeof(float));
    glVertexArrayAttribBinding(m_sphereVao, 1, 0);
    m_capacity = capacity;
    ++m_bufferGeneration;
}

void ParticleRenderer::upload(const ParticleInstance* instances, size_t n) {
    reserve(n);
    if (n > 0) glNamedBufferSubData(m_instanceBuffer, 0, GLsizeiptr(n * sizeof(ParticleInstance)), instances);
    m_count = n;
}

// The flat-depth variant: sphere.frag with COREBOX_FLAT_DEPTH defined after its #version line.
GLuint ParticleRenderer::sphereProgram(bool exactDepth) {
    if (exactDepth) return m_sphereProgram;
    if (!m_flatSphereProgram) {
        std::string text = shaders::sphere_frag;
        const size_t versionEnd = text.find('\n');
        if (text.compare(0, 9, "#version ") != 0 || versionEnd == std::string::npos)
            throw RenderError("sphere.frag: its first line is not a #version line");
        text.insert(versionEnd + 1, "#define COREBOX_FLAT_DEPTH\n");
        m_flatSphereProgram = buildSphereProgram(text.c_str(), "sphere (flat depth)");
    }
    return m_flatSphereProgram;
}

void ParticleRenderer::render(const OrbitCamera& camera, const std::array<float, 3>& boxSize, const RenderStyle& style,
                              int width, int height) {
    glViewport(0, 0, width, height);
    glClearColor(style.background[0], style.background[1], style.background[2], 1.0f);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDisable(GL_BLEND);

    const float aspect = float(width) / float(height);
    const glm::mat4 view = camera.view();
    const glm::mat4 projection = camera.projection(aspect);

    if (m_count > 0) {
        const GLuint program = sphereProgram(style.exactDepth);
        glUseProgram(program);
        glUniformMatrix4fv(glGetUniformLocation(program, "uView"), 1, GL_FALSE, glm::value_ptr(view));
        glUniformMatrix4fv(glGetUniformLocation(program, "uProjection"), 1, GL_FALSE, glm::value_ptr(projection));
        glUniform1i(glGetUniformLocation(program, "uColorMode"), style.mode == ColorMode::Species ? 0 : 1);
        const GLsizei paletteSize = GLsizei(std::min<size_t>(style.palette.size(), 32));
        if (paletteSize > 0) {
            glUniform3fv(glGetUniformLocation(program, "uPalette"), paletteSize, style.palette[0].data());
        }
        glUniform1i(glGetUniformLocation(program, "uPaletteSize"), paletteSize);
        glUniform2f(glGetUniformLocation(program, "uKeyRange"), style.keyMin, style.keyMax);
        glBindVertexArray(m_sphereVao);
        // The impostors lie just before each sphere's tangent plane nearest the eye (sphere.vert): a sphere whose
        // nearest point is nearer than the near plane but whose centre is beyond it would lose its whole
        // quad to the near clip. Clamped, the quad is drawn, and its fragments' hit depths (clamped as the
        // old centre-plane quads' were; with flat depth, the quad's own) decide what shows.
        glEnable(GL_DEPTH_CLAMP);
        glDrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, GLsizei(m_count));
        glDisable(GL_DEPTH_CLAMP);
    }
    if (style.showBox) drawBox(projection * view, boxSize, style);
    if (style.showLegend) drawLegend(style, width, height);
    glBindVertexArray(0);
    glUseProgram(0);
}

void ParticleRenderer::drawBox(const glm::mat4& viewProjection, const std::array<float, 3>& b, const RenderStyle& style) {
    std::vector<float> lines;
    const float corner[8][3] = {{0, 0, 0},          {b[0], 0, 0},          {0, b[1], 0},          {b[0], b[1], 0},
                                {0, 0, b[2]},       {b[0], 0, b[2]},       {0, b[1], b[2]},       {b[0], b[1], b[2]}};
    const int edges[12][2] = {{0, 1}, {2, 3}, {4, 5}, {6, 7}, {0, 2}, {1, 3}, {4, 6}, {5, 7}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
    for (const auto& e : edges) {
        for (int k = 0; k < 2; ++k) lines.insert(lines.end(), corner[e[k]], corner[e[k]] + 3);
    }
    glNamedBufferSubData(m_lineBuffer, 0, GLsizeiptr(lines.size() * sizeof(float)), lines.data());
    glUseProgram(m_lineProgram);
    glUniformMatrix4fv(glGetUniformLocation(m_lineProgram, "uViewProjection"), 1, GL_FALSE, glm::value_ptr(viewProjection));
    glUniform4f(glGetUniformLocation(m_lineProgram, "uColor"), style.boxColor[0], style.boxColor[1], style.boxColor[2], 1.0f);
    glBindVertexArray(m_lineVao);
    glDrawArrays(GL_LINES, 0, 24);
}

float ParticleRenderer::legendScale(int height) { return height >= 480 ? 2.0f : 1.0f; }

float ParticleRenderer::legendBottomHeight(ColorMode mode, int height) {
    // drawLegend's speed key: margin + 10 (value labels) + 8 (bar) + 12 (key label), in legend pixels.
    return mode == ColorMode::Species ? 0.0f : (10.0f + 10.0f + 8.0f + 12.0f) * legendScale(height);
}

void ParticleRenderer::drawLegend(const RenderStyle& style, int width, int height) {
    std::vector<OverlayVertex> v;
    const std::array<float, 4> text{0.88f, 0.9f, 0.93f, 1.0f};
    const float scale = legendScale(height);
    const float margin = 10.0f * scale;
    if (style.mode == ColorMode::Species) {
        float y = margin;
        for (const LegendEntry& e : style.speciesLegend) {
            const float s = 8.0f * scale;
            addQuad(v, margin, y, margin + s, y + s, {e.color[0], e.color[1], e.color[2], 1.0f});
            addText(v, margin + s + 4.0f * scale, y, e.label, scale, text);
            y += s + 4.0f * scale;
        }
    } else {
        const float barWidth = std::min(180.0f * scale, 0.4f * float(width));
        const float barHeight = 8.0f * scale;
        const float x0 = margin, y1 = float(height) - margin - 10.0f * scale;
        // The label's top is legendBottomHeight above the bottom edge.
        addText(v, x0, y1 - barHeight - 12.0f * scale, style.keyLabel, scale, text);
        addQuad(v, x0, y1 - barHeight, x0 + barWidth, y1, text, 0.0f, 1.0f);
        addText(v, x0, y1 + 3.0f * scale, formatValue(style.keyMin), scale, text);
        const std::string maxLabel = formatValue(style.keyMax);
        addText(v, x0 + barWidth - float(stb_easy_font_width(const_cast<char*>(maxLabel.c_str()))) * scale, y1 + 3.0f * scale,
                maxLabel, scale, text);
    }
    if (v.empty()) return;
    glNamedBufferData(m_overlayBuffer, GLsizeiptr(v.size() * sizeof(OverlayVertex)), v.data(), GL_STREAM_DRAW);
    glDisable(GL_DEPTH_TEST);
    glUseProgram(m_overlayProgram);
    glUniform2f(glGetUniformLocation(m_overlayProgram, "uViewportSize"), float(width), float(height));
    glBindVertexArray(m_overlayVao);
    glDrawArrays(GL_TRIANGLES, 0, GLsizei(v.size()));
    glEnable(GL_DEPTH_TEST);
}

}  // namespace corebox
