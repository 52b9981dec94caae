#include "glfw_window.h"

#include <epoxy/gl.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <cstdlib>

namespace corebox {
namespace {
std::string g_lastError;
void onError(int, const char* description) { g_lastError = description ? description : "unknown GLFW error"; }
}  // namespace

bool GlfwWindow::displayAvailable() {
    const char* x = std::getenv("DISPLAY");
    const char* wayland = std::getenv("WAYLAND_DISPLAY");
    return (x && *x) || (wayland && *wayland);
}

bool GlfwWindow::isSoftwareRenderer(const std::string& glRenderer) {
    for (const char* name : {"llvmpipe", "softpipe", "swrast", "Software Rasterizer"})
        if (glRenderer.find(name) != std::string::npos) return true;
    return false;
}

namespace {
// The display's GL_RENDERER, from an invisible 1x1 window ("" when none can be made: the real window
// then reports why).
std::string probeRenderer() {
    glfwWindowHint(GLFW_VISIBLE, GLFW_FALSE);
    glfwWindowHint(GLFW_SAMPLES, 0);
    GLFWwindow* probe = glfwCreateWindow(1, 1, "", nullptr, nullptr);
    glfwDefaultWindowHints();
    if (!probe) return "";
    glfwMakeContextCurrent(probe);
    const GLubyte* name = glGetString(GL_RENDERER);
    const std::string renderer = name ? reinterpret_cast<const char*>(name) : "";
    glfwMakeContextCurrent(nullptr);
    glfwDestroyWindow(probe);
    return renderer;
}

void contextHints() {
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
}
}  // namespace

GlfwWindow::GlfwWindow(int width, int height, const std::string& title, int samples) {
    glfwSetErrorCallback(onError);
    if (!glfwInit()) throw PlatformError("cannot open a window: " + g_lastError);
    if (samples == kAutoSamples) {
        contextHints();
        samples = autoSamples(probeRenderer());
    }
    contextHints();
    glfwWindowHint(GLFW_SAMPLES, samples > 1 ? samples : 0);
    m_window = glfwCreateWindow(width, height, title.c_str(), nullptr, nullptr);
    if (!m_window) {
        glfwTerminate();
        throw PlatformError("cannot create an OpenGL 4.5 core window: " + g_lastError);
    }
    glfwMakeContextCurrent(m_window);
    if (epoxy_gl_version() < 45) {
        glfwDestroyWindow(m_window);
        glfwTerminate();
        throw PlatformError("the display's OpenGL is " + std::to_string(epoxy_gl_version()) + ", below the 4.5 needed");
    }
    // GLFW_SAMPLES is a hint: what the default framebuffer got.
    GLint got = 0;
    glGetIntegerv(GL_SAMPLES, &got);
    m_samples = got > 1 ? int(got) : 0;
    setVsync(true);
}

GlfwWindow::~GlfwWindow() {
    if (m_window) glfwDestroyWindow(m_window);
    glfwTerminate();
}

void GlfwWindow::setTitle(const std::string& title) { glfwSetWindowTitle(m_window, title.c_str()); }

void GlfwWindow::setVsync(bool on) {
    m_vsync = on;
    glfwSwapInterval(on ? 1 : 0);
}

bool GlfwWindow::shouldClose() const { return glfwWindowShouldClose(m_window); }

void GlfwWindow::framebufferSize(int* width, int* height) const { glfwGetFramebufferSize(m_window, width, height); }

std::string GlfwWindow::glDescription() const {
    return std::string(reinterpret_cast<const char*>(glGetString(GL_RENDERER))) + ", OpenGL " +
           reinterpret_cast<const char*>(glGetString(GL_VERSION));
}

}  // namespace corebox
