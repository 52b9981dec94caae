#include "offscreen_target.h"

#include <algorithm>
#include <cstring>
#include <string>

#include "gl_program.h"
#include "image_io.h"

namespace corebox {
namespace {

void checkComplete(GLuint fbo, const char* what) {
    const GLenum status = glCheckNamedFramebufferStatus(fbo, GL_FRAMEBUFFER);
    if (status != GL_FRAMEBUFFER_COMPLETE) {
        throw RenderError(std::string("offscreen ") + what + " framebuffer incomplete (status 0x" + std::to_string(status) + ")");
    }
}

}  // namespace

OffscreenTarget::OffscreenTarget(int width, int height, int samples) : m_width(width), m_height(height) {
    GLint maxSamples = 1;
    glGetIntegerv(GL_MAX_SAMPLES, &maxSamples);
    samples = samples > 1 ? std::min(samples, int(maxSamples)) : 0;  // 0: storage without multisampling
    m_samples = samples > 1 ? samples : 0;
    glCreateRenderbuffers(1, &m_msColor);
    glNamedRenderbufferStorageMultisample(m_msColor, samples, GL_RGBA8, width, height);
    glCreateRenderbuffers(1, &m_msDepth);
    glNamedRenderbufferStorageMultisample(m_msDepth, samples, GL_DEPTH_COMPONENT24, width, height);
    glCreateFramebuffers(1, &m_msFbo);
    glNamedFramebufferRenderbuffer(m_msFbo, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, m_msColor);
    glNamedFramebufferRenderbuffer(m_msFbo, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, m_msDepth);
    checkComplete(m_msFbo, "drawing");

    glCreateRenderbuffers(1, &m_resolveColor);
    glNamedRenderbufferStorage(m_resolveColor, GL_RGBA8, width, height);
    glCreateFramebuffers(1, &m_resolveFbo);
    glNamedFramebufferRenderbuffer(m_resolveFbo, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, m_resolveColor);
    checkComplete(m_resolveFbo, "resolve");
}

OffscreenTarget::~OffscreenTarget() {
    const GLuint fbos[2] = {m_msFbo, m_resolveFbo};
    glDeleteFramebuffers(2, fbos);
    const GLuint rbs[3] = {m_msColor, m_msDepth, m_resolveColor};
    glDeleteRenderbuffers(3, rbs);
}

void OffscreenTarget::bind() const { glBindFramebuffer(GL_FRAMEBUFFER, m_msFbo); }

void OffscreenTarget::readPixels(std::vector<uint8_t>& rgba) const {
    glBlitNamedFramebuffer(m_msFbo, m_resolveFbo, 0, 0, m_width, m_height, 0, 0, m_width, m_height, GL_COLOR_BUFFER_BIT,
                           GL_NEAREST);
    const size_t row = size_t(m_width) * 4;
    rgba.resize(row * size_t(m_height));
    glBindFramebuffer(GL_READ_FRAMEBUFFER, m_resolveFbo);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, m_width, m_height, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    flipRows(rgba, m_width, m_height);
}

}  // namespace corebox
