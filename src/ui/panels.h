// ImGui panels (Dear ImGui 1.86): the control panel, the speed histogram against Maxwell-Boltzmann,
// time plots and the performance readout. They edit SimulationControls and ViewSettings and read
// the views; they never call GL or a backend.
#pragma once

#include <string>
#include <vector>

#include "simulation_controls.h"
#include "ui_views.h"

namespace corebox {

void drawControlPanel(SimulationControls& controls, ViewSettings& view, PanelActions& actions,
                      const std::vector<std::string>& presetPaths, const std::string& status);
// place: give the window its default position and size on first use (the HUD places them itself).
void drawSpeedHistogram(const SpeedView& speeds, bool place = true);
void drawTimePlots(const ObservableHistory& history, bool place = true);
void drawPerformance(const PerformanceView& performance, bool place = true);
void drawHelp(bool* open);

// Read-only heads-up display for dumped frames: histogram, plots and performance in one column.
void drawHud(const SpeedView& speeds, const ObservableHistory& history, const PerformanceView& performance, float width,
             float height);

}  // namespace corebox
