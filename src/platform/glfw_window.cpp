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

GlfwWindow::GlfwWindow(int width, int height, const std::string& title) {
    glfwSetErrorCallback(onError);
    if (!glfwInit()) throw PlatformError("cannot open a window: " + g_lastError);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    glfwWindowHint(GLFW_SAMPLES, 4);
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
