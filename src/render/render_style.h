// How particles are drawn: the style (palette or colormap, legend, box, background). What the
// renderer knows of particles is the instance layout of kernels/particle_instance.h (a position, a
// radius and a colour key each), which backends write directly; it knows nothing else of the
// simulation. The key is a palette index (colour by species) or a value mapped through the colormap
// (colour by speed).
#pragma once

#include <array>
#include <string>
#include <vector>

#include "particle_instance.h"

namespace corebox {

// What the colour key holds decides how it is coloured: one enum for both sides.
using ColorMode = InstanceKey;

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
