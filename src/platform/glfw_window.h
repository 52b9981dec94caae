// A GLFW 3.3 window with an OpenGL 4.5 core context (loaded through libepoxy), resizable, with a
// vsync switch. Throws PlatformError when there is no display or no GL 4.5.
#pragma once

#include <string>

#include "platform_error.h"

struct GLFWwindow;

namespace corebox {

class GlfwWindow {
public:
    GlfwWindow(int width, int height, const std::string& title);
    ~GlfwWindow();
    GlfwWindow(const GlfwWindow&) = delete;
    GlfwWindow& operator=(const GlfwWindow&) = delete;

    GLFWwindow* handle() const { return m_window; }
    void setTitle(const std::string& title);
    void setVsync(bool on);
    bool shouldClose() const;
    void framebufferSize(int* width, int* height) const;
    std::string glDescription() const;

    static bool displayAvailable();

private:
    GLFWwindow* m_window = nullptr;
    bool m_vsync = true;
};

}  // namespace corebox
