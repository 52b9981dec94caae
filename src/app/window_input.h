// Mouse and keyboard of the window run: edge-triggered key presses turned into panel actions, and
// orbit (left drag), pan (right drag) and zoom (wheel) of the camera. The wheel arrives through a
// GLFW callback; its accumulator is this object's state, reached through the window's user pointer
// (no global), and is used up once per frame.
#pragma once

#include <vector>

#include "orbit_camera.h"
#include "panel_data.h"

struct GLFWwindow;

namespace corebox {

class WindowInput {
public:
    // Installs the scroll callback: construct before ImGuiLayer, which chains to the callback it finds.
    explicit WindowInput(GLFWwindow* window);
    ~WindowInput();
    WindowInput(const WindowInput&) = delete;
    WindowInput& operator=(const WindowInput&) = delete;

    // Space pause/run, Right single step, R reset, F12 screenshot, H panels, F1 help, Esc quit; none
    // while ImGui has the keyboard (typing a number into the panel must not pause the run).
    void readKeys(bool uiWantsKeyboard, DisplaySettings& display, PanelActions& actions, bool* quit);
    // Moves the camera by the drags and wheel turns since the last call, unless ImGui has the mouse.
    void moveCamera(OrbitCamera& camera, bool uiWantsMouse);

private:
    bool pressed(int key);
    static void onScroll(GLFWwindow* window, double dx, double dy);

    GLFWwindow* m_window;
    std::vector<char> m_down;  // per GLFW key code: down at the last look
    double m_scroll = 0;       // wheel steps since the last moveCamera
    double m_lastX = 0, m_lastY = 0;
};

}  // namespace corebox
