// Error types a user can act on. Each maps to one exit code of `corebox run` (DESIGN.md sec. 3):
// InputError 2 (bad scene, file or flag), InstabilityError 3 (blow-up detected), DeviceError 4.
#pragma once

#include <string>

#include "corebox/errors.h"  // InputError, InstabilityError, DeviceError: shared with the public API

namespace corebox {

// An InputError's message names the file, line and key where one is known
// ("scene.toml:12: species[1].mass: must be > 0"): "file:line: key: message", leaving out the parts that are unknown (line <= 0, empty key).
std::string locatedMessage(const std::string& file, long line, const std::string& key, const std::string& message);

}  // namespace corebox
