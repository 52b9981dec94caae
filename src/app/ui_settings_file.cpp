#include "ui_settings_file.h"

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace corebox {

UiSettingsFile UiSettingsFile::standard() {
    const char* xdg = std::getenv("XDG_CONFIG_HOME");
    const char* home = std::getenv("HOME");
    std::string base = xdg && *xdg ? xdg : (home && *home ? std::string(home) + "/.config" : ".");
    return UiSettingsFile(base + "/corebox");
}

UiSettingsFile::UiSettingsFile(std::string directory) : m_directory(std::move(directory)) {
    std::error_code ec;
    std::filesystem::create_directories(m_directory, ec);  // best effort: settings are a convenience
}

std::string UiSettingsFile::imguiIniPath() const { return m_directory + "/imgui.ini"; }

void UiSettingsFile::load(DisplaySettings& display) const {
    std::ifstream in(m_directory + "/settings.ini");
    std::string line;
    while (std::getline(in, line)) {
        std::istringstream s(line);
        std::string key, eq;
        int value = 0;
        if (!(s >> key >> eq >> value) || eq != "=") continue;
        if (key == "steps_per_frame" && value >= 1) display.stepsPerFrame = value;
        else if (key == "vsync") display.vsync = value != 0;
        else if (key == "color_by_speed") display.colorBySpeed = value != 0;
        else if (key == "show_panel") display.showPanel = value != 0;
    }
}

void UiSettingsFile::save(const DisplaySettings& display) const {
    std::ofstream out(m_directory + "/settings.ini");
    out << "steps_per_frame = " << display.stepsPerFrame << "\nvsync = " << int(display.vsync) << "\ncolor_by_speed = " << int(display.colorBySpeed)
        << "\nshow_panel = " << int(display.showPanel) << "\n";
}

}  // namespace corebox
