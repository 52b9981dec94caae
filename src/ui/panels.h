// ImGui panels (Dear ImGui 1.86): the control panel, the speed histogram against Maxwell-Boltzmann,
// time plots, the performance readout and speed against accuracy. They edit LiveControls and DisplaySettings and read
// the panel data; they never call GL or a backend.
#pragma once

#include <string>
#include <vector>

#include "live_controls.h"
#include "panel_data.h"

namespace corebox {

void drawControlPanel(LiveControls& controls, DisplaySettings& display, PanelActions& actions,
                      const std::vector<std::string>& presetPaths, const std::string& status);
// place: give the window its default position and size on first use (the HUD places them itself).
void drawSpeedHistogram(const SpeedDistributionData& speeds, bool place = true);
void drawTimePlots(const ObservableHistory& history, bool place = true, float plotHeight = 40);
void drawPerformance(const PerformanceData& performance, bool place = true);
void drawSpeedAccuracy(const SpeedAccuracyData& data, bool place = true);
void drawHelp(bool* open);

// Read-only heads-up display for dumped frames: histogram and plots in one column on the right,
// performance at the bottom left, above the `bottomReserved` pixels of the frame's own legend.
void drawHud(const SpeedDistributionData& speeds, const ObservableHistory& history, const PerformanceData& performance, float width,
             float height, float bottomReserved);

}  // namespace corebox
