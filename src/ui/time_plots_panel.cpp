#include <imgui.h>

#include <algorithm>
#include <string>

#include "panels.h"

namespace corebox {
namespace {

void plot(const char* label, const std::vector<float>& values, float height) {
    if (values.empty()) {
        ImGui::TextDisabled("%s: no data yet", label);
        return;
    }
    const auto [lo, hi] = std::minmax_element(values.begin(), values.end());
    const float pad = std::max(1e-12f, 0.05f * (*hi - *lo));
    char overlay[96];
    std::snprintf(overlay, sizeof overlay, "%s  %.5g", label, double(values.back()));
    ImGui::PlotLines(label, values.data(), int(values.size()), 0, overlay, *lo - pad, *hi + pad,
                     ImVec2(ImGui::GetContentRegionAvail().x, height));
}

}  // namespace

void drawTimePlots(const ObservableHistory& h, bool place, float plotHeight) {
    if (place) {
        ImGui::SetNextWindowPos(ImVec2(1180, 540), ImGuiCond_FirstUseEver);
        ImGui::SetNextWindowSize(ImVec2(410, 350), ImGuiCond_FirstUseEver);
    }
    ImGui::Begin("Time plots");
    plot("kinetic", h.kinetic, plotHeight);
    plot("potential", h.potential, plotHeight);
    plot("total", h.total, plotHeight);
    plot("dissipated", h.dissipated, plotHeight);
    plot("conserved drift (rel.)", h.drift, plotHeight);
    plot("temperature", h.temperature, plotHeight);
    if (!h.target.empty()) {
        if (h.target.back() > 0) ImGui::Text("target T %.4g", double(h.target.back()));
        else ImGui::TextDisabled("no thermostat");
    }
    plot("collisions / step", h.collisionsPerStep, plotHeight);
    // Two routes to one pressure (pressure.h): they agree in the time average.
    plot("pressure (walls)", h.pressureWall, plotHeight);
    plot("pressure (virial)", h.pressureVirial, plotHeight);
    ImGui::End();
}

void drawPerformance(const PerformanceData& p, bool place) {
    if (place) ImGui::SetNextWindowPos(ImVec2(380, 10), ImGuiCond_FirstUseEver);
    ImGui::Begin("Performance", nullptr, ImGuiWindowFlags_AlwaysAutoResize);
    ImGui::Text("%s: %s", p.backend.c_str(), p.device.c_str());
    ImGui::TextWrapped("forces: %s", p.forces.c_str());
    if (!p.integrator.empty()) ImGui::TextWrapped("%s", p.integrator.c_str());
    ImGui::Text("%.1f steps/s   %.1f frames/s   %d steps/frame", p.stepsPerSecond, p.framesPerSecond, p.stepsPerFrame);
    if (p.pairForces) ImGui::Text("pair interactions/s: %.3g", p.pairInteractionsPerSecond);
    else ImGui::TextDisabled("no pair forces (hard spheres)");
    ImGui::Text("ms per frame: steps %.2f = force %.2f + integrate %.2f + collide %.2f", p.msStep, p.msForce, p.msIntegrate,
                p.msCollide);
    ImGui::Text("observe %.2f  particles->GL %.2f  render %.2f", p.msObserve, p.msInterop, p.msRender);
    ImGui::End();
}

void drawHud(const SpeedDistributionData& speeds, const ObservableHistory& history, const PerformanceData& performance, float width,
             float height, float bottomReserved) {
    const float column = std::min(420.0f, 0.34f * width);
    ImGui::SetNextWindowPos(ImVec2(width - column - 8, 8), ImGuiCond_Always);
    ImGui::SetNextWindowSize(ImVec2(column, height * 0.62f), ImGuiCond_Always);
    drawSpeedHistogram(speeds, false);
    // The time plots share what is left of the column: ten plots and a line of text, with the
    // window's title bar and padding (about 50 px) and ImGui's item spacing (about 6 px each).
    const float plotsHeight = height * 0.38f - 20;
    ImGui::SetNextWindowPos(ImVec2(width - column - 8, height * 0.62f + 12), ImGuiCond_Always);
    ImGui::SetNextWindowSize(ImVec2(column, plotsHeight), ImGuiCond_Always);
    drawTimePlots(history, false, std::clamp((plotsHeight - 50) / 10 - 6, 12.0f, 40.0f));
    // Bottom left, its lower edge above the renderer's colour key (the window sizes itself).
    ImGui::SetNextWindowPos(ImVec2(8, height - bottomReserved - 8), ImGuiCond_Always, ImVec2(0, 1));
    drawPerformance(performance, false);
}

}  // namespace corebox
