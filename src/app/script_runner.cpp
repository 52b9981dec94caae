#include "script_runner.h"

#include <cstdio>
#include <cstdlib>

#include "display_vocabulary.h"
#include "errors.h"

namespace corebox {
namespace {

double number(const ScriptCommand& c, size_t index, const std::string& path) {
    char* end = nullptr;
    const double v = std::strtod(c.words[index].c_str(), &end);
    if (*end != '\0') throw InputError(locatedMessage(path, c.line, c.words[1], "not a number: '" + c.words[index] + "'"));
    return v;
}

// The setting's value (third word) as a name from `table`.
template <class Enum>
Enum choice(const ScriptCommand& c, const Vocabulary<Enum>& table, const std::string& path) {
    Enum value;
    if (!table.parse(c.words[2], &value)) throw InputError(locatedMessage(path, c.line, c.words[1], table.unknown(c.words[2])));
    return value;
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
        else if (what == "method") controls.setMethod(choice(c, methodTable(), path));
        else if (what == "precision") controls.setPrecision(choice(c, precisionTable(), path));
        else if (what == "thermostat") controls.setThermostatKind(choice(c, thermostatTable(), path));
        else if (what == "color") display.colorBySpeed = choice(c, colorModeTable(), path) == ColorMode::Speed;
    }
    return effects;
}

}  // namespace corebox
