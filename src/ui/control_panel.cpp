#include <imgui.h>

#include <cstdio>
#include <string>

#include "panels.h"

namespace corebox {
namespace {

// "rk4 (order 4)": the name, and the note when the table has one.
template <class Enum>
std::string termLabel(const Term<Enum>& term) {
    return *term.note ? std::string(term.name) + " (" + term.note + ")" : std::string(term.name);
}

// A combo box over a vocabulary table: the labels are its names (with the note, where there is one)
// and the selection maps back to a value through the table, never through the enum's numbering.
template <class Enum>
bool comboBox(const char* label, const Vocabulary<Enum>& table, Enum current, Enum* chosen) {
    bool changed = false;
    const size_t index = table.indexOf(current);
    const std::string preview = index < table.size() ? termLabel(table.begin()[index]) : "?";
    if (ImGui::BeginCombo(label, preview.c_str())) {
        for (const Term<Enum>& term : table) {
            const bool selected = term.value == current;
            if (ImGui::Selectable(termLabel(term).c_str(), selected) && !selected) {
                *chosen = term.value;
                changed = true;
            }
            if (selected) ImGui::SetItemDefaultFocus();
        }
        ImGui::EndCombo();
    }
    return changed;
}

// Sliders and drags keep typed values (Ctrl+click) within their range too.
constexpr ImGuiSliderFlags kClamped = ImGuiSliderFlags_AlwaysClamp;
constexpr ImGuiSliderFlags kClampedLog = ImGuiSliderFlags_AlwaysClamp | ImGuiSliderFlags_Logarithmic;

bool inputDouble(const char* label, double* value, double step, const char* format = "%.4g") {
    return ImGui::InputDouble(label, value, step, step * 10, format, ImGuiInputTextFlags_EnterReturnsTrue);
}

void liveSection(LiveControls& c) {
    const Scene& s = c.live();
    ImGui::TextDisabled("Live: applies at the next step");

    ThermostatKind thermostat;
    if (comboBox("thermostat", thermostatTable(), s.thermostat.kind, &thermostat)) c.setThermostatKind(thermostat);
    float target = float(s.thermostat.temperature);
    if (ImGui::SliderFloat("target T", &target, 0.05f, 10.0f, "%.3f", kClampedLog)) c.setTargetTemperature(target);
    float tau = float(s.thermostat.tau);
    if (ImGui::SliderFloat("tau", &tau, 0.005f, 10.0f, "%.3f", kClampedLog)) c.setThermostatTau(tau);

    Method method;
    if (comboBox("integrator", methodTable(), s.integrator.method, &method)) c.setMethod(method);
    double dt = s.integrator.dt;
    if (inputDouble("dt", &dt, 1e-4, "%.2e")) c.setDt(dt);
    for (const Term<Precision>& term : precisionTable()) {
        if (&term != precisionTable().begin()) ImGui::SameLine();
        if (ImGui::RadioButton(term.name, s.integrator.precision == term.value)) c.setPrecision(term.value);
    }

    float e = float(s.interaction.restitution);
    if (ImGui::SliderFloat("restitution", &e, 0.0f, 1.0f, "%.3f", kClamped)) c.setRestitution(e);
    float ew = float(s.box.wallRestitution);
    if (ImGui::SliderFloat("wall restitution", &ew, 0.0f, 1.0f, "%.3f", kClamped)) c.setWallRestitution(ew);
    float g[3] = {float(s.interaction.gravity[0]), float(s.interaction.gravity[1]), float(s.interaction.gravity[2])};
    if (ImGui::DragFloat3("gravity", g, 0.01f, -20.0f, 20.0f, "%.3f", kClamped)) c.setGravity({g[0], g[1], g[2]});

    if (s.species.size() > 1 && ImGui::TreeNode("species mixing x_ij")) {
        static float like = 1.0f, unlike = 0.5f;
        ImGui::SliderFloat("like", &like, 0.0f, 2.0f, "%.3f", kClamped);
        ImGui::SliderFloat("unlike", &unlike, 0.0f, 2.0f, "%.3f", kClamped);
        if (ImGui::Button("apply like/unlike")) c.setLikeUnlikeMixing(like, unlike);
        for (size_t i = 0; i < s.species.size(); ++i) {
            for (size_t j = i; j < s.species.size(); ++j) {
                float x = float(s.mixing(i, j));
                const std::string label = "x " + s.species[i].name + "-" + s.species[j].name;
                if (ImGui::SliderFloat(label.c_str(), &x, 0.0f, 2.0f, "%.3f", kClamped)) c.setMixing(i, j, x);
            }
        }
        ImGui::TreePop();
    }
}

void restartSection(LiveControls& c, PanelActions& actions) {
    ImGui::TextDisabled("Needs Reset: counts, masses, radii, box, seed");
    const Scene& p = c.pending();
    for (size_t k = 0; k < p.species.size(); ++k) {
        ImGui::PushID(int(k));
        ImGui::Text("%s", p.species[k].name.c_str());
        int count = int(p.species[k].count);
        if (ImGui::InputInt("count", &count, 10, 100, ImGuiInputTextFlags_EnterReturnsTrue)) c.setSpeciesCount(k, count);
        double mass = p.species[k].mass, radius = p.species[k].radius;
        if (inputDouble("mass", &mass, 0.1)) c.setSpeciesMass(k, mass);
        if (inputDouble("radius", &radius, 0.05)) c.setSpeciesRadius(k, radius);
        ImGui::PopID();
    }
    double box[3] = {p.box.size[0], p.box.size[1], p.box.size[2]};
    if (ImGui::InputScalarN("box", ImGuiDataType_Double, box, 3, nullptr, nullptr, "%.3g", ImGuiInputTextFlags_EnterReturnsTrue)) {
        c.setBoxSize({box[0], box[1], box[2]});
    }
    int seed = int(p.init.seed);
    if (ImGui::InputInt("seed", &seed, 1, 10, ImGuiInputTextFlags_EnterReturnsTrue) && seed >= 0) c.setSeed(uint64_t(seed));
    if (c.restartPending()) ImGui::TextColored(ImVec4(1.0f, 0.75f, 0.3f, 1.0f), "edits pending: press Reset");
    if (ImGui::Button("Reset (R)")) actions.reset = true;
}

}  // namespace

void drawControlPanel(LiveControls& controls, DisplaySettings& display, PanelActions& actions,
                      const std::vector<std::string>& presetPaths, const std::string& status) {
    ImGui::SetNextWindowPos(ImVec2(10, 10), ImGuiCond_FirstUseEver);
    ImGui::SetNextWindowSize(ImVec2(360, 700), ImGuiCond_FirstUseEver);
    ImGui::Begin("corebox");
    if (ImGui::Button(display.paused ? "Run (Space)" : "Pause (Space)")) display.paused = !display.paused;
    ImGui::SameLine();
    if (ImGui::Button("Step (Right)")) actions.singleStep = true;
    ImGui::SameLine();
    if (ImGui::Button("Screenshot (F12)")) actions.screenshot = true;
    ImGui::SliderInt("steps/frame", &display.stepsPerFrame, 1, 200, "%d", kClamped);
    ImGui::Checkbox("vsync", &display.vsync);
    ImGui::SameLine();
    ImGui::Checkbox("colour by speed", &display.colorBySpeed);
    if (!status.empty()) ImGui::TextWrapped("%s", status.c_str());
    // A typed value the scene rules refuse (dt <= 0, a mass of 1e300, ...) changes nothing; say why.
    if (!controls.lastRefusal().empty())
        ImGui::TextColored(ImVec4(1.0f, 0.45f, 0.35f, 1.0f), "refused: %s", controls.lastRefusal().c_str());

    if (ImGui::CollapsingHeader("Live parameters", ImGuiTreeNodeFlags_DefaultOpen)) liveSection(controls);
    if (ImGui::CollapsingHeader("Scene (restart)")) restartSection(controls, actions);
    if (ImGui::CollapsingHeader("Presets and files")) {
        for (const std::string& path : presetPaths) {
            const std::string name = path.substr(path.find_last_of('/') + 1);
            if (ImGui::Selectable(name.c_str())) actions.loadPreset = path;
        }
        static char savePath[256] = "scene.toml";
        ImGui::InputText("file", savePath, sizeof savePath);
        if (ImGui::Button("Save scene as TOML")) actions.saveScenePath = savePath;
    }
    ImGui::End();
}

void drawHelp(bool* open) {
    if (!*open) return;
    ImGui::SetNextWindowPos(ImVec2(400, 60), ImGuiCond_FirstUseEver);
    ImGui::Begin("Keys (F1)", open, ImGuiWindowFlags_AlwaysAutoResize);
    const char* keys[][2] = {{"Space", "pause / run"},        {"Right", "single step"},       {"R", "reset (applies scene edits)"},
                             {"F12", "screenshot (PNG)"},     {"H", "hide / show the panels"}, {"F1", "this help"},
                             {"Esc", "quit"},                 {"left drag", "orbit"},          {"right drag", "pan"},
                             {"wheel", "zoom"}};
    for (const auto& k : keys) {
        ImGui::TextUnformatted(k[0]);
        ImGui::SameLine(110);
        ImGui::TextUnformatted(k[1]);
    }
    ImGui::End();
}

}  // namespace corebox
