// Framebuffer object to render into without a window (headless frames, screenshots, tests): colour +
// depth, multisampled unless asked for one sample, resolved into a single-sample buffer that is read
// back top-down.
#pragma once

#include <epoxy/gl.h>

#include <cstdint>
#include <vector>

namespace corebox {

class OffscreenTarget {
public:
    // samples: a pixel's samples; 0 or 1: a single-sample buffer. Throws RenderError when incomplete.
    OffscreenTarget(int width, int height, int samples = 4);
    ~OffscreenTarget();
    OffscreenTarget(const OffscreenTarget&) = delete;
    OffscreenTarget& operator=(const OffscreenTarget&) = delete;

    void bind() const;  // draw into the (multisampled) buffer
    // Resolves and reads RGBA8 pixels, rows top to bottom (image order).
    void readPixels(std::vector<uint8_t>& rgba) const;

    int width() const { return m_width; }
    int height() const { return m_height; }
    int samples() const { return m_samples; }  // a pixel's samples (0: none)

private:
    int m_width, m_height;
    int m_samples = 0;
    GLuint m_msFbo = 0, m_msColor = 0, m_msDepth = 0;
    GLuint m_resolveFbo = 0, m_resolveColor = 0;
};

}  // namespace corebox
