// Dear ImGui's context and its GLFW and OpenGL 3 backends (Debian's libimgui 1.86). With a GLFW
// window it takes input from it; without one (headless HUD) it draws into whatever framebuffer is
// bound, at a size given each frame. The panels themselves (src/ui) never touch GL.
#pragma once

#include <string>

struct GLFWwindow;

namespace corebox {

class ImGuiLayer {
public:
    // iniPath: where ImGui keeps window layout ("" for none: headless frames stay reproducible).
    ImGuiLayer(GLFWwindow* window, const std::string& iniPath);
    ~ImGuiLayer();
    ImGuiLayer(const ImGuiLayer&) = delete;
    ImGuiLayer& operator=(const ImGuiLayer&) = delete;

    void beginFrame(int width, int height, double deltaSeconds);
    void endFrame();  // renders into the bound framebuffer

    bool wantsMouse() const;
    bool wantsKeyboard() const;

private:
    bool m_window;
    std::string m_iniPath;
};

}  // namespace corebox
