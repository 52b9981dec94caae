#include <imgui.h>

#include <algorithm>
#include <cmath>

#include "maxwell_boltzmann.h"
#include "panels.h"

namespace corebox {
namespace {

double referencePdf(const SpeedSeries& s, double v, double t) {
    if (s.mixture.empty()) return maxwellBoltzmannPdf(v, s.mass, t);
    double f = 0;
    for (const auto& wm : s.mixture) f += wm[0] * maxwellBoltzmannPdf(v, wm[1], t);
    return f;
}

// Bars of the measured density with the analytic MB curves at the measured temperature (solid) and
// at the target (dashed), drawn over the histogram's frame.
void plotSeries(const SpeedSeries& s, double maxSpeed, double target, float width, float height) {
    const float top = *std::max_element(s.density.begin(), s.density.end());
    float peak = top;
    for (int k = 0; k <= 64; ++k) {
        const double v = maxSpeed * k / 64.0;
        peak = std::max(peak, float(referencePdf(s, v, std::max(s.temperatureEquipartition, 1e-9))));
    }
    peak *= 1.1f;
    const ImVec2 origin = ImGui::GetCursorScreenPos();
    ImGui::PushStyleColor(ImGuiCol_PlotHistogram, ImVec4(s.color[0], s.color[1], s.color[2], 0.55f));
    ImGui::PlotHistogram("##h", s.density.data(), int(s.density.size()), 0, nullptr, 0.0f, peak, ImVec2(width, height));
    ImGui::PopStyleColor();
    ImDrawList* draw = ImGui::GetWindowDrawList();
    const ImGuiStyle& style = ImGui::GetStyle();
    const float x0 = origin.x + style.FramePadding.x, x1 = origin.x + width - style.FramePadding.x;
    const float y0 = origin.y + height - style.FramePadding.y, y1 = origin.y + style.FramePadding.y;
    auto curve = [&](double t, ImU32 color, bool dashed) {
        if (t <= 0) return;
        ImVec2 previous{};
        for (int k = 0; k <= 96; ++k) {
            const double v = maxSpeed * k / 96.0;
            const float y = float(referencePdf(s, v, t)) / peak;
            const ImVec2 p(x0 + (x1 - x0) * float(k) / 96.0f, y0 + (y1 - y0) * std::min(y, 1.0f));
            if (k > 0 && (!dashed || k % 4 < 2)) draw->AddLine(previous, p, color, 2.0f);
            previous = p;
        }
    };
    curve(s.temperatureEquipartition, IM_COL32(255, 255, 255, 230), false);
    curve(target, IM_COL32(255, 190, 60, 230), true);
}

}  // namespace

void drawSpeedHistogram(const SpeedDistributionData& speeds, bool place) {
    if (place) {
        ImGui::SetNextWindowPos(ImVec2(1180, 10), ImGuiCond_FirstUseEver);
        ImGui::SetNextWindowSize(ImVec2(410, 520), ImGuiCond_FirstUseEver);
    }
    ImGui::Begin("Speed distribution vs Maxwell-Boltzmann");
    ImGui::PushStyleColor(ImGuiCol_Text, ImGui::GetStyleColorVec4(ImGuiCol_TextDisabled));
    ImGui::TextWrapped("bars: measured; white: MB at the measured T; orange dashed: MB at the target T");
    ImGui::PopStyleColor();
    const float width = ImGui::GetContentRegionAvail().x;
    for (const SpeedSeries& s : speeds.species) {
        if (s.count == 0 || s.density.empty()) continue;
        ImGui::PushID(s.name.c_str());
        ImGui::TextColored(ImVec4(s.color[0], s.color[1], s.color[2], 1.0f), "%s (%lld)", s.name.c_str(), (long long)s.count);
        plotSeries(s, speeds.maxSpeed, speeds.targetTemperature, width, 90.0f);
        const bool pass = s.ksStatistic < s.ksCritical;
        ImGui::Text("KS D = %.4f  (critical %.4f at alpha 0.01: %s)", s.ksStatistic, s.ksCritical, pass ? "MB" : "not MB");
        ImGui::Text("T equipartition %.4f   T from distribution %.4f", s.temperatureEquipartition, s.temperatureDistribution);
        ImGui::PopID();
    }
    ImGui::End();
}

}  // namespace corebox
