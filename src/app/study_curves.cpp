#include "study_curves.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>

#include <nlohmann/json.hpp>

#include "errors.h"
#include "vocabulary.h"

namespace corebox {
namespace {

// Colours by method, in the study's order (matplotlib's tab10 and two more), so the panel and the
// charts in docs/ agree.
std::array<float, 3> methodColor(const std::string& method) {
    static const std::map<std::string, std::array<float, 3>> colors = {
        {"euler", {0.12f, 0.47f, 0.71f}},      {"rk2", {1.00f, 0.50f, 0.05f}},     {"rk4", {0.17f, 0.63f, 0.17f}},
        {"dp5", {0.84f, 0.15f, 0.16f}},        {"hairer10", {0.58f, 0.40f, 0.74f}}, {"verlet", {0.55f, 0.34f, 0.29f}},
        {"forest_ruth", {0.89f, 0.47f, 0.76f}}, {"pefrl", {0.50f, 0.50f, 0.50f}},   {"blanes_moan", {0.74f, 0.74f, 0.13f}},
        {"yoshida6", {0.09f, 0.75f, 0.81f}},   {"yoshida8", {0.20f, 0.20f, 0.90f}}};
    const auto it = colors.find(method);
    return it != colors.end() ? it->second : std::array<float, 3>{1, 1, 1};
}

nlohmann::json readStudy(const std::string& path) {
    std::ifstream in(path);
    if (!in) throw InputError("--study '" + path + "': cannot be read");
    nlohmann::json j;
    try {
        in >> j;
    } catch (const std::exception& e) {
        throw InputError("--study '" + path + "': not JSON (" + e.what() + ")");
    }
    if (!j.is_object() || !j.contains("runs") || !j["runs"].is_array())
        throw InputError("--study '" + path + "': not a study file (no \"runs\"; write one with corebox study SCENE --out PREFIX)");
    return j;
}

}  // namespace

std::vector<AccuracySeries> loadStudyCurves(const std::string& path) {
    const nlohmann::json j = readStudy(path);
    std::map<std::string, AccuracySeries> series;
    std::vector<std::string> order;
    for (const nlohmann::json& run : j["runs"]) {
        if (run.value("outcome", "") != "ok") continue;
        const nlohmann::json& rate = run["energy_drift_rate"];
        const double cost = run.value("force_passes_per_time", 0.0);
        if (!rate.is_number() || !(cost > 0)) continue;
        const double drift = std::fabs(rate.get<double>());
        if (!(drift > 0)) continue;
        const std::string method = run.value("method", "?");
        const bool adaptive = run.value("tolerance", 0.0) > 0;
        const std::string label = method + (adaptive ? " adaptive " : " ") + run.value("precision", "?");
        if (!series.count(label)) {
            order.push_back(label);
            series[label].label = label;
            series[label].color = methodColor(method);
            series[label].method = method + (adaptive ? " adaptive" : "");
            series[label].faint = run.value("precision", "") == "fp32";
        }
        series[label].points.push_back({cost, drift});
    }
    std::vector<AccuracySeries> out;
    for (const std::string& label : order) {
        AccuracySeries s = series[label];
        std::sort(s.points.begin(), s.points.end());
        out.push_back(std::move(s));
    }
    return out;
}

bool chooseIntegratorFromStudy(const std::string& path, const Scene& scene, IntegratorDef* chosen, std::string* summary) {
    const nlohmann::json j = readStudy(path);
    const double longRun = j.value("long_run", 0.0);
    const double tolerance = scene.integrator.tolerance;
    const nlohmann::json* best = nullptr;
    int candidates = 0;
    for (const nlohmann::json& run : j["runs"]) {
        const nlohmann::json& error = run["energy_error_max"];
        if (run.value("outcome", "") != "ok" || run.value("tolerance", 0.0) > 0 || !error.is_number() || !(longRun > 0)) continue;
        ++candidates;
        if (error.get<double>() / longRun > 0.5 * tolerance) continue;
        if (!best || run.value("force_passes_per_time", 0.0) < (*best).value("force_passes_per_time", 0.0)) best = &run;
    }
    char line[500];
    if (!best) {
        std::snprintf(line, sizeof line, "no run of the study %s (%d finished fixed-step runs) meets an energy error of %g per unit time",
                      path.c_str(), candidates, tolerance);
        *summary = line;
        return false;
    }
    Method method = Method::Verlet;
    Precision precision = Precision::Fp64;
    if (!methodTable().parse((*best).value("method", ""), &method) || !precisionTable().parse((*best).value("precision", ""), &precision))
        throw InputError("--study '" + path + "': a run names an unknown method or precision");
    *chosen = scene.integrator;
    chosen->automatic = false;
    chosen->adaptive = false;
    chosen->method = method;
    chosen->precision = precision;
    chosen->dt = (*best).value("dt", scene.integrator.dt);
    std::snprintf(line, sizeof line,
                  "integrator auto (energy error <= %g per unit time): %s %s dt = %g from the study %s: %.2g per unit time over t = %g, "
                  "%.4g force passes per unit time, the cheapest in force passes of its %d finished runs that meet it",
                  tolerance, methodName(method), precisionName(precision), chosen->dt, path.c_str(),
                  (*best)["energy_error_max"].get<double>() / longRun, longRun, (*best).value("force_passes_per_time", 0.0), candidates);
    *summary = line;
    return true;
}

std::string findStudyFile(const Scene& scene, const std::string& backendName) {
    if (scene.sourcePath.empty()) return "";
    namespace fs = std::filesystem;
    const fs::path source(scene.sourcePath);
    const fs::path results = source.parent_path().parent_path() / "docs" / "results";
    const std::string stem = source.stem().string();
    const char* mine = backendName == "cuda" ? "h200" : "cpu";
    const char* other = backendName == "cuda" ? "cpu" : "h200";
    for (const char* tag : {mine, other}) {
        const fs::path candidate = results / ("study_" + stem + "_" + tag + ".json");
        std::error_code ec;
        if (fs::is_regular_file(candidate, ec)) return candidate.string();
    }
    return "";
}

}  // namespace corebox
