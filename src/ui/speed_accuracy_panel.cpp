// The speed-vs-accuracy panel (panel_data.h: SpeedAccuracyData): a log-log chart drawn with ImGui's
// draw list, since the panels use no plotting library. Decades are gridded and labelled; the range
// covers every study line and live point, widened to whole decades.
#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "panels.h"

namespace corebox {
namespace {

struct LogRange {
    double lo = 0, hi = 0;  // decades (log10)
    void include(double v) {
        if (!(v > 0) || !std::isfinite(v)) return;
        const double d = std::log10(v);
        if (lo == hi && lo == 0) lo = hi = d;
        lo = std::min(lo, d);
        hi = std::max(hi, d);
    }
    void settle() {
        lo = std::floor(lo);
        hi = std::ceil(hi);
        if (hi - lo < 1) hi = lo + 1;
    }
};

ImU32 colorOf(const std::array<float, 3>& c, float alpha = 1) { return ImGui::ColorConvertFloat4ToU32(ImVec4(c[0], c[1], c[2], alpha)); }

}  // namespace

void drawSpeedAccuracy(const SpeedAccuracyData& data, bool place) {
    if (place) {
        ImGui::SetNextWindowPos(ImVec2(380, 600), ImGuiCond_FirstUseEver);
        ImGui::SetNextWindowSize(ImVec2(500, 290), ImGuiCond_FirstUseEver);
    }
    ImGui::Begin("Speed vs accuracy");
    if (data.studySource.empty()) ImGui::TextDisabled("no study of this scene (corebox study SCENE --out ..., then --study FILE)");
    else ImGui::TextDisabled("lines: %s", data.studySource.c_str());
    LogRange x, y;
    for (const AccuracySeries& s : data.study)
        for (const auto& p : s.points) {
            x.include(p[0]);
            y.include(p[1]);
        }
    for (const AccuracyPoint& p : data.live) {
        x.include(p.cost);
        y.include(p.driftRate);
    }
    if (x.lo == x.hi && y.lo == y.hi && data.live.empty()) {
        ImGui::TextDisabled("no points yet");
        ImGui::End();
        return;
    }
    x.settle();
    y.settle();

    const float legendWidth = 150;
    const ImVec2 origin = ImGui::GetCursorScreenPos();
    const ImVec2 avail = ImGui::GetContentRegionAvail();
    const float left = 46, bottom = 34;
    const ImVec2 size(std::max(120.0f, avail.x - legendWidth - left), std::max(80.0f, avail.y - bottom));
    const ImVec2 p0(origin.x + left, origin.y), p1(p0.x + size.x, p0.y + size.y);
    auto at = [&](double cost, double drift) {
        const double fx = (std::log10(cost) - x.lo) / (x.hi - x.lo), fy = (std::log10(drift) - y.lo) / (y.hi - y.lo);
        return ImVec2(p0.x + float(fx) * size.x, p1.y - float(fy) * size.y);
    };
    ImDrawList* draw = ImGui::GetWindowDrawList();
    const ImU32 grid = IM_COL32(90, 90, 100, 255), text = IM_COL32(200, 200, 210, 255);
    draw->AddRect(p0, p1, grid);
    char label[64];
    for (int d = int(x.lo); d <= int(x.hi); ++d) {
        const float px = at(std::pow(10.0, d), std::pow(10.0, y.lo)).x;
        draw->AddLine(ImVec2(px, p0.y), ImVec2(px, p1.y), grid);
        std::snprintf(label, sizeof label, "1e%d", d);
        draw->AddText(ImVec2(px - 10, p1.y + 2), text, label);
    }
    for (int d = int(y.lo); d <= int(y.hi); ++d) {
        const float py = at(std::pow(10.0, x.lo), std::pow(10.0, d)).y;
        draw->AddLine(ImVec2(p0.x, py), ImVec2(p1.x, py), grid);
        std::snprintf(label, sizeof label, "1e%d", d);
        draw->AddText(ImVec2(origin.x + 2, py - 7), text, label);
    }
    draw->AddText(ImVec2(p0.x + size.x * 0.5f - 90, p1.y + 16), text, "force passes per unit time");
    draw->AddText(ImVec2(p0.x + 4, p0.y + 2), text, "|energy drift| per unit time");

    draw->PushClipRect(p0, p1, true);
    for (const AccuracySeries& s : data.study) {
        for (size_t k = 0; k < s.points.size(); ++k) {
            const ImVec2 q = at(s.points[k][0], s.points[k][1]);
            const float alpha = s.faint ? 0.35f : 0.9f;
            draw->AddCircleFilled(q, 2.5f, colorOf(s.color, alpha));
            if (k > 0) draw->AddLine(at(s.points[k - 1][0], s.points[k - 1][1]), q, colorOf(s.color, alpha), 1.5f);
        }
    }
    for (const AccuracyPoint& p : data.live) {
        if (!(p.cost > 0 && p.driftRate > 0)) continue;
        const ImVec2 q = at(p.cost, p.driftRate);
        draw->AddCircle(q, p.running ? 7.0f : 5.0f, p.running ? IM_COL32(255, 230, 60, 255) : IM_COL32(255, 255, 255, 255), 0, 2.0f);
        draw->AddText(ImVec2(q.x + 8, q.y - 7), IM_COL32(255, 255, 255, 255), p.label.c_str());
    }
    draw->PopClipRect();

    // The legend: one line per study series, then the live points' values.
    ImGui::SetCursorScreenPos(ImVec2(p1.x + 8, origin.y));
    ImGui::BeginGroup();
    std::vector<std::string> listed;
    for (const AccuracySeries& s : data.study) {
        if (std::find(listed.begin(), listed.end(), s.method) != listed.end()) continue;
        listed.push_back(s.method);
        ImGui::TextColored(ImVec4(s.color[0], s.color[1], s.color[2], 1), "%s", s.method.c_str());
    }
    if (!data.study.empty()) ImGui::TextDisabled("fp64 bright, fp32 faint");
    for (const AccuracyPoint& p : data.live) {
        if (p.cost > 0 && p.driftRate > 0)
            ImGui::Text("%s%s: %.3g, %.2g", p.running ? "> " : "", p.label.c_str(), p.cost, p.driftRate);
        else
            ImGui::TextDisabled("%s%s: measuring", p.running ? "> " : "", p.label.c_str());
    }
    ImGui::EndGroup();
    ImGui::SetCursorScreenPos(ImVec2(origin.x, p1.y + bottom));
    ImGui::End();
}

}  // namespace corebox
