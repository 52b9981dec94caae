// Where the window keeps its settings between runs: $XDG_CONFIG_HOME/corebox (or ~/.config/corebox):
// imgui.ini for the panel layout (ImGui's own) and settings.ini for the display settings
// (steps/frame, vsync, colour mode, panel shown), as key = value lines.
#pragma once

#include <string>

#include "panel_data.h"

namespace corebox {

class UiSettingsFile {
public:
    static UiSettingsFile standard();
    explicit UiSettingsFile(std::string directory);

    std::string imguiIniPath() const;
    void load(DisplaySettings& display) const;  // missing or unreadable file: defaults stay
    void save(const DisplaySettings& display) const;

private:
    std::string m_directory;
};

}  // namespace corebox
