#include "imgui_layer.h"

#include <epoxy/gl.h>
#include <imgui.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>

#include "platform_error.h"

namespace corebox {

ImGuiLayer::ImGuiLayer(GLFWwindow* window, const std::string& iniPath) : m_window(window != nullptr), m_iniPath(iniPath) {
    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGuiIO& io = ImGui::GetIO();
    io.IniFilename = m_iniPath.empty() ? nullptr : m_iniPath.c_str();
    ImGui::StyleColorsDark();
    ImGui::GetStyle().WindowRounding = 4.0f;
    ImGui::GetStyle().Colors[ImGuiCol_WindowBg].w = 0.88f;
    if (window && !ImGui_ImplGlfw_InitForOpenGL(window, true)) throw PlatformError("ImGui GLFW backend failed to start");
    if (!ImGui_ImplOpenGL3_Init("#version 450")) throw PlatformError("ImGui OpenGL 3 backend failed to start");
}

ImGuiLayer::~ImGuiLayer() {
    ImGui_ImplOpenGL3_Shutdown();
    if (m_window) ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
}

void ImGuiLayer::beginFrame(int width, int height, double deltaSeconds) {
    ImGui_ImplOpenGL3_NewFrame();
    if (m_window) {
        ImGui_ImplGlfw_NewFrame();
    } else {
        ImGuiIO& io = ImGui::GetIO();
        io.DisplaySize = ImVec2(float(width), float(height));
        io.DeltaTime = float(deltaSeconds > 0 ? deltaSeconds : 1.0 / 60.0);
    }
    ImGui::NewFrame();
}

void ImGuiLayer::endFrame() {
    ImGui::Render();
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
}

bool ImGuiLayer::wantsMouse() const { return ImGui::GetIO().WantCaptureMouse; }
bool ImGuiLayer::wantsKeyboard() const { return ImGui::GetIO().WantCaptureKeyboard; }

}  // namespace corebox
