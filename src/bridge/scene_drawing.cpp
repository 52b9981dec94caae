#include "scene_drawing.h"

#include <algorithm>
#include <cmath>

namespace corebox {

void buildInstances(const ParticleState& state, const Scene& scene, ColorMode mode, std::vector<ParticleInstance>& out) {
    out.resize(state.size());
    for (size_t i = 0; i < state.size(); ++i) {
        const int32_t s = state.species[i];
        out[i] = particleInstanceOf(state.position[i], state.velocity[i], s, scene.species[size_t(s)].radius, mode);
    }
}

RenderStyle renderStyleFor(const Scene& scene, ColorMode mode, double speedMax) {
    RenderStyle style;
    style.mode = mode;
    double lightest = 0;
    for (const SpeciesDef& s : scene.species) {
        style.palette.push_back(s.color);
        style.speciesLegend.push_back({s.name + " (" + std::to_string(s.count) + ")", s.color});
        if (s.count > 0) lightest = lightest == 0 ? s.mass : std::min(lightest, s.mass);
    }
    if (speedMax <= 0) {
        double t = scene.init.temperature;
        if (scene.thermostat.kind != ThermostatKind::None) t = std::max(t, scene.thermostat.temperature);
        speedMax = 3.5 * std::sqrt(std::max(t, 1e-6) / std::max(lightest, 1e-12));
    }
    style.keyMin = 0.0f;
    style.keyMax = float(speedMax);
    style.keyLabel = "speed |v|";
    return style;
}

}  // namespace corebox
