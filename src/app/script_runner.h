// Carries out script commands (script.h) on the controls and display settings of a run; what the frame
// loop itself must do (screenshot, reset, quit) comes back as effects.
#pragma once

#include <string>

#include "script.h"
#include "live_controls.h"
#include "panel_data.h"

namespace corebox {

struct ScriptEffects {
    bool quit = false;
    bool reset = false;
    std::string screenshotPath;
};

// Throws InputError naming the script's file and line for a bad value.
ScriptEffects runScriptCommand(const ScriptCommand& command, const std::string& scriptPath, LiveControls& controls,
                               DisplaySettings& display);

}  // namespace corebox
