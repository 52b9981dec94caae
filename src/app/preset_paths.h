// The scenes the panel offers under "Presets and files": the presets shipped in assets/ and the
// scene files beside the one running, each once (canonical paths), assets first.
#pragma once

#include <string>
#include <vector>

namespace corebox {

std::vector<std::string> presetPaths(const std::string& sceneDir);

}  // namespace corebox
