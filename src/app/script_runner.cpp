#include "script_runner.h"

#include <cmath>
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

// A whole number in [lo, hi] (an index, a count): anything else is refused, not truncated.
int64_t wholeNumber(const ScriptCommand& c, size_t index, const std::string& path, int64_t lo, int64_t hi, std::string* refusal) {
    const double v = number(c, index, path);
    if (!(v >= double(lo) && v <= double(hi)) || v != std::floor(v)) {
        *refusal = c.words[1] + ": '" + c.words[index] + "' is not a whole number from " + std::to_string(lo) + " to " +
                   std::to_string(hi);
        return lo;
    }
    return int64_t(v);
}

// Steps between frames at most: a frame every 10^5 steps is already a batch run.
constexpr int64_t kMaxStepsPerFrame = 100000;

}  // namespace

ScriptEffects runScriptCommand(const ScriptCommand& c, const std::string& path, LiveControls& controls, DisplaySettings& display,
                               bool announce) {
    ScriptEffects effects;
    std::string text;
    for (const std::string& w : c.words) text += (text.empty() ? "" : " ") + w;
    std::string refusal;  // why a `set` was refused: the run goes on without it
    const std::string& command = c.words[0];
    if (command == "quit") effects.quit = true;
    else if (command == "pause") display.paused = true;
    else if (command == "resume") display.paused = false;
    else if (command == "reset") effects.reset = true;
    else if (command == "screenshot") effects.screenshotPath = c.words[1];
    else if (command == "set") {
        const std::string& what = c.words[1];
        if (what == "temperature") refusal = controls.setTargetTemperature(number(c, 2, path));
        else if (what == "tau") refusal = controls.setThermostatTau(number(c, 2, path));
        else if (what == "dt") refusal = controls.setDt(number(c, 2, path));
        else if (what == "restitution") refusal = controls.setRestitution(number(c, 2, path));
        else if (what == "wall-restitution") refusal = controls.setWallRestitution(number(c, 2, path));
        else if (what == "gravity") refusal = controls.setGravity({number(c, 2, path), number(c, 3, path), number(c, 4, path)});
        else if (what == "mixing") {
            const int64_t species = int64_t(controls.live().species.size());
            const int64_t i = wholeNumber(c, 2, path, 0, species - 1, &refusal);
            const int64_t j = wholeNumber(c, 3, path, 0, species - 1, &refusal);
            if (refusal.empty()) refusal = controls.setMixing(size_t(i), size_t(j), number(c, 4, path));
        } else if (what == "steps-per-frame") {
            const int64_t k = wholeNumber(c, 2, path, 1, kMaxStepsPerFrame, &refusal);
            if (refusal.empty()) display.stepsPerFrame = int(k);
        } else if (what == "method") refusal = controls.setMethod(choice(c, methodTable(), path));
        else if (what == "precision") refusal = controls.setPrecision(choice(c, precisionTable(), path));
        else if (what == "thermostat") refusal = controls.setThermostatKind(choice(c, thermostatTable(), path));
        else if (what == "color") display.colorBySpeed = choice(c, colorModeTable(), path) == ColorMode::Speed;
    }
    // A refused value changes nothing and the run goes on, as in the panel; the line says so.
    if (refusal.empty()) {
        if (announce) std::fprintf(stderr, "[corebox] script step %lld: %s\n", (long long)c.step, text.c_str());
    } else
        std::fprintf(stderr, "[corebox] warning: %s:%ld: script step %lld: '%s' refused, nothing changed: %s\n", path.c_str(), c.line,
                     (long long)c.step, text.c_str(), refusal.c_str());
    return effects;
}

}  // namespace corebox
