#include "preset_paths.h"

#include <glob.h>

#include <algorithm>
#include <filesystem>

namespace corebox {

std::vector<std::string> presetPaths(const std::string& sceneDir) {
    std::vector<std::string> out;
    const std::string assets = std::filesystem::path(COREBOX_DEFAULT_SCENE).parent_path().string();
    for (const std::string& dir : {assets, sceneDir}) {
        glob_t g{};
        if (glob((dir + "/*.toml").c_str(), 0, nullptr, &g) == 0) {
            for (size_t k = 0; k < g.gl_pathc; ++k) {
                const std::string path = std::filesystem::weakly_canonical(g.gl_pathv[k]).string();
                if (std::find(out.begin(), out.end(), path) == out.end()) out.push_back(path);
            }
        }
        globfree(&g);
    }
    return out;
}

}  // namespace corebox
