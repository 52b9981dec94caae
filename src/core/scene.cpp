#include "scene.h"

namespace corebox {

int64_t Scene::particleCount() const {
    int64_t n = 0;
    for (const SpeciesDef& s : species) n += s.count;
    return n;
}

double Scene::mixing(size_t i, size_t j) const {
    if (interaction.mixing.empty()) return 1.0;
    return interaction.mixing.at(i).at(j);
}

StepParameters stepParametersOf(const Scene& scene) {
    return StepParameters{scene.integrator, scene.interaction, scene.box, scene.species};
}

}  // namespace corebox
