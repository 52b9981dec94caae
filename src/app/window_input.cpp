#include "window_input.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <cmath>

namespace corebox {

WindowInput::WindowInput(GLFWwindow* window) : m_window(window), m_down(GLFW_KEY_LAST + 1, 0) {
    glfwSetWindowUserPointer(window, this);
    glfwSetScrollCallback(window, onScroll);
    glfwGetCursorPos(window, &m_lastX, &m_lastY);
}

WindowInput::~WindowInput() {
    glfwSetScrollCallback(m_window, nullptr);
    glfwSetWindowUserPointer(m_window, nullptr);
}

void WindowInput::onScroll(GLFWwindow* window, double, double dy) {
    if (auto* input = static_cast<WindowInput*>(glfwGetWindowUserPointer(window))) input->m_scroll += dy;
}

bool WindowInput::pressed(int key) {
    const bool down = glfwGetKey(m_window, key) == GLFW_PRESS;
    const bool edge = down && !m_down[size_t(key)];
    m_down[size_t(key)] = down;
    return edge;
}

void WindowInput::readKeys(bool uiWantsKeyboard, DisplaySettings& display, PanelActions& actions, bool* quit) {
    if (uiWantsKeyboard) return;
    if (pressed(GLFW_KEY_SPACE)) display.paused = !display.paused;
    if (pressed(GLFW_KEY_RIGHT)) actions.singleStep = true;
    if (pressed(GLFW_KEY_R)) actions.reset = true;
    if (pressed(GLFW_KEY_F12)) actions.screenshot = true;
    if (pressed(GLFW_KEY_H)) display.showPanel = !display.showPanel;
    if (pressed(GLFW_KEY_F1)) display.showHelp = !display.showHelp;
    if (pressed(GLFW_KEY_ESCAPE)) *quit = true;
}

void WindowInput::moveCamera(OrbitCamera& camera, bool uiWantsMouse) {
    double x = 0, y = 0;
    glfwGetCursorPos(m_window, &x, &y);
    if (!uiWantsMouse) {
        if (glfwGetMouseButton(m_window, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS) {
            camera.orbit(-0.005f * float(x - m_lastX), 0.005f * float(y - m_lastY));
        }
        if (glfwGetMouseButton(m_window, GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS) {
            camera.pan(0.0015f * float(x - m_lastX), 0.0015f * float(y - m_lastY));
        }
        if (m_scroll != 0) camera.zoom(float(std::pow(0.9, m_scroll)));
    }
    m_scroll = 0;
    m_lastX = x;
    m_lastY = y;
}

}  // namespace corebox
