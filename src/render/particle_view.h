// What the renderer knows of particles: a position, a radius and a colour key per instance. It
// knows nothing else of the simulation. The key is a palette index (colour by species) or a value
// mapped through the colormap (colour by speed). The layout is the GL instance buffer's, and the
// CUDA interop kernel writes exactly this struct.
#pragma once

#include <array>
#include <string>
#include <vector>

namespace corebox {

struct ParticleInstance {
    float x, y, z;
    float radius;
    float colorKey;
};
static_assert(sizeof(ParticleInstance) == 5 * sizeof(float), "tightly packed: shared with GL and CUDA");

enum class ColorMode { Species, Speed };

struct LegendEntry {
    std::string label;
    std::array<float, 3> color;
};

struct RenderStyle {
    ColorMode mode = ColorMode::Species;
    std::vector<std::array<float, 3>> palette;   // colour per key, species mode (at most 32)
    std::vector<LegendEntry> speciesLegend;      // swatches with labels, species mode
    float keyMin = 0.0f, keyMax = 1.0f;          // colormap range, speed mode
    std::string keyLabel = "speed";              // colour bar title, speed mode
    bool showLegend = true;
    bool showBox = true;
    std::array<float, 3> background{0.055f, 0.06f, 0.075f};
    std::array<float, 3> boxColor{0.55f, 0.6f, 0.68f};
};

}  // namespace corebox
