#include "script_runner.h"

#include <cstdio>
#include <cstdlib>

#include "errors.h"

namespace corebox {
namespace {

double number(const ScriptCommand& c, size_t index, const std::string& path) {
    char* end = nullptr;
    const double v = std::strtod(c.words[index].c_str(), &end);
    if (*end != '\0') throw InputError(locatedMessage(path, c.line, c.words[1], "not a number: '" + c.words[index] + "'"));
    return v;
}

}  // namespace

ScriptEffects runScriptCommand(const ScriptCommand& c, const std::string& path, LiveControls& controls, DisplaySettings& display) {
    ScriptEffects effects;
    std::string text;
    for (const std::string& w : c.words) text += (text.empty() ? "" : " ") + w;
    std::fprintf(stderr, "[corebox] script step %lld: %s\n", (long long)c.step, text.c_str());
    const std::string& command = c.words[0];
    if (command == "quit") effects.quit = true;
    else if (command == "pause") display.paused = true;
    else if (command == "resume") display.paused = false;
    else if (command == "reset") effects.reset = true;
    else if (command == "screenshot") effects.screenshotPath = c.words[1];
    else if (command == "set") {
        const std::string& what = c.words[1];
        if (what == "temperature") controls.setTargetTemperature(number(c, 2, path));
        else if (what == "tau") controls.setThermostatTau(number(c, 2, path));
        else if (what == "dt") controls.setDt(number(c, 2, path));
        else if (what == "restitution") controls.setRestitution(number(c, 2, path));
        else if (what == "wall-restitution") controls.setWallRestitution(number(c, 2, path));
        else if (what == "gravity") controls.setGravity({number(c, 2, path), number(c, 3, path), number(c, 4, path)});
        else if (what == "mixing") controls.setMixing(size_t(number(c, 2, path)), size_t(number(c, 3, path)), number(c, 4, path));
        else if (what == "steps-per-frame") display.stepsPerFrame = std::max(1, int(number(c, 2, path)));
        else if (what == "method") {
            Method m;
            if (!parseMethod(c.words[2], &m)) throw InputError(locatedMessage(path, c.line, "method", "unknown method '" + c.words[2] + "'"));
            controls.setMethod(m);
        } else if (what == "precision") {
            if (c.words[2] != "fp32" && c.words[2] != "fp64") throw InputError(locatedMessage(path, c.line, "precision", "expected fp32 or fp64"));
            controls.setPrecision(c.words[2] == "fp32" ? Precision::Fp32 : Precision::Fp64);
        } else if (what == "thermostat") {
            const std::string& k = c.words[2];
            if (k == "bussi") controls.setThermostatKind(ThermostatKind::Bussi);
            else if (k == "rescale") controls.setThermostatKind(ThermostatKind::Rescale);
            else if (k == "none") controls.setThermostatKind(ThermostatKind::None);
            else throw InputError(locatedMessage(path, c.line, "thermostat", "expected bussi, rescale or none"));
        } else if (what == "color") {
            if (c.words[2] != "species" && c.words[2] != "speed") throw InputError(locatedMessage(path, c.line, "color", "expected species or speed"));
            display.colorBySpeed = c.words[2] == "speed";
        }
    }
    return effects;
}

}  // namespace corebox
