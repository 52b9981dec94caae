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

void drawTimePlots(const ObservableHistory& h, bool place) {
    if (place) {
        ImGui::SetNextWindowPos(ImVec2(1180, 540), ImGuiCond_FirstUseEver);
        ImGui::SetNextWindowSize(ImVec2(410, 350), ImGuiCond_FirstUseEver);
    }
    ImGui::Begin("Time plots");
    plot("kinetic", h.kinetic, 40);
    plot("potential", h.potential, 40);
    plot("total", h.total, 40);
    plot("dissipated", h.dissipated, 40);
    plot("conserved drift (rel.)", h.drift, 40);
    plot("temperature", h.temperature, 40);
    if (!h.target.empty()) {
        if (h.target.back() > 0) ImGui::Text("target T %.4g", double(h.target.back()));
        else ImGui::TextDisabled("no thermostat");
    }
    plot("collisions / step", h.collisionsPerStep, 40);
    // Two routes to one pressure (pressure.h): they agree in the time average.
    plot("pressure (walls)", h.pressureWall, 40);
    plot("pressure (virial)", h.pressureVirial, 40);
    ImGui::End();
}

void drawPerformance(const PerformanceData& p, bool place) {
    if (place) ImGui::SetNextWindowPos(ImVec2(380, 10), ImGuiCond_FirstUseEver);
    ImGui::Begin("Performance", nullptr, ImGuiWindowFlags_AlwaysAutoResize);
    ImGui::Text("%s: %s", p.backend.c_str(), p.device.c_str());
    ImGui::Text("%.1f steps/s   %.1f frames/s   %d steps/frame", p.stepsPerSecond, p.framesPerSecond, p.stepsPerFrame);
    if (p.pairForces) ImGui::Text("pair interactions/s: %.3g", p.pairInteractionsPerSecond);
    else ImGui::TextDisabled("no pair forces (hard spheres)");
    ImGui::Text("ms per frame: steps %.2f = force %.2f + integrate %.2f + collide %.2f", p.msStep, p.msForce, p.msIntegrate,
                p.msCollide);
    ImGui::Text("observe %.2f  particles->GL %.2f  render %.2f", p.msObserve, p.msInterop, p.msRender);
    ImGui::End();
}

void drawHud(const SpeedDistributionData& speeds, const ObservableHistory& history, const PerformanceData& performance, float width,
             float height) {
    const float column = std::min(420.0f, 0.34f * width);
    ImGui::SetNextWindowPos(ImVec2(width - column - 8, 8), ImGuiCond_Always);
    ImGui::SetNextWindowSize(ImVec2(column, height * 0.62f), ImGuiCond_Always);
    drawSpeedHistogram(speeds, false);
    ImGui::SetNextWindowPos(ImVec2(width - column - 8, height * 0.62f + 12), ImGuiCond_Always);
    ImGui::SetNextWindowSize(ImVec2(column, height * 0.38f - 20), ImGuiCond_Always);
    drawTimePlots(history, false);
    ImGui::SetNextWindowPos(ImVec2(8, height - 110), ImGuiCond_Always);
    drawPerformance(performance, false);
}

}  // namespace corebox
