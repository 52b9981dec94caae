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

// Throws InputError naming the script's file and line for a value that is not a number or a name.
// A value the scene rules refuse (set dt -1, set mixing 0 1 -1, ...) changes nothing, as in the panel,
// and a warning names the line and the rule; the run goes on. `announce`: also a line for each
// command carried out.
ScriptEffects runScriptCommand(const ScriptCommand& command, const std::string& scriptPath, LiveControls& controls,
                               DisplaySettings& display, bool announce = true);

}  // namespace corebox
