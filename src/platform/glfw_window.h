// A GLFW 3.3 window with an OpenGL 4.5 core context (loaded through libepoxy), resizable, with a
// vsync switch. Throws PlatformError when there is no display or no GL 4.5.
//
// Multisampling: 4 samples a pixel on a GPU. On a software rasteriser (Mesa's llvmpipe, as under Xvfb or
// on a machine without a GPU driver) the default framebuffer then holds four samples a pixel that every
// sphere fragment writes and every buffer swap resolves: the sandbox's 2,000 balls at 1280x720 took
// 20 ms to draw and 8 ms to present with them, 10.7 and 1 without (a 2-core machine, llvmpipe 15).
// kAutoSamples therefore asks the display first (an invisible 1x1 window) and takes 0 samples on a
// software renderer, 4 otherwise.
#pragma once

#include <string>

#include "platform_error.h"

struct GLFWwindow;

namespace corebox {

class GlfwWindow {
public:
    static constexpr int kAutoSamples = -1;

    // samples: multisampling of the default framebuffer (0 or 1: none), or kAutoSamples (above).
    GlfwWindow(int width, int height, const std::string& title, int samples = kAutoSamples);
    ~GlfwWindow();
    GlfwWindow(const GlfwWindow&) = delete;
    GlfwWindow& operator=(const GlfwWindow&) = delete;

    GLFWwindow* handle() const { return m_window; }
    void setTitle(const std::string& title);
    void setVsync(bool on);
    bool shouldClose() const;
    void framebufferSize(int* width, int* height) const;
    std::string glDescription() const;
    int samples() const { return m_samples; }  // what the default framebuffer got (0: none)

    // Whether a GL_RENDERER string names a software rasteriser (llvmpipe, softpipe, swrast).
    static bool isSoftwareRenderer(const std::string& glRenderer);
    // kAutoSamples' choice for a renderer: 0 on a software rasteriser, 4 otherwise.
    static int autoSamples(const std::string& glRenderer) { return isSoftwareRenderer(glRenderer) ? 0 : 4; }

    static bool displayAvailable();

private:
    GLFWwindow* m_window = nullptr;
    bool m_vsync = true;
    int m_samples = 0;
};

}  // namespace corebox
