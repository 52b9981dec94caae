#include "device_model.h"

#include <algorithm>

#include "pair_table.h"

namespace corebox {

double DeviceModel::maxRadius() const { return radius.empty() ? 0.0 : *std::max_element(radius.begin(), radius.end()); }

double DeviceModel::smallestContact() const {
    double smallest = 0;
    for (double a : radius) {
        if (a > 0 && (smallest == 0 || 2 * a < smallest)) smallest = 2 * a;
    }
    return smallest;
}

DeviceModel deviceModelOf(const StepParameters& parameters) {
    DeviceModel model;
    model.pairs = buildPairTable(parameters);
    model.anyPairForce = std::any_of(model.pairs.begin(), model.pairs.end(), [](const PairCoefficients<double>& p) { return p.eps4 != 0.0; });
    for (const SpeciesDef& s : parameters.species) {
        model.mass.push_back(s.mass);
        model.radius.push_back(s.radius);
    }
    for (int a = 0; a < 3; ++a) {
        model.box[a] = parameters.box.size[size_t(a)];
        model.gravity[a] = parameters.interaction.gravity[size_t(a)];
    }
    for (const SpeciesDef& s : parameters.species) {
        model.acceleration.push_back(model.gravity + Vec3<double>{s.acceleration[0], s.acceleration[1], s.acceleration[2]});
    }
    model.hasCutoff = parameters.interaction.cutoff > 0;
    model.cutoff = parameters.interaction.cutoff;
    model.skin = parameters.interaction.skin;
    model.restitution = parameters.interaction.restitution;
    model.wallRestitution = parameters.box.wallRestitution;
    model.elasticBelowSpeed = parameters.interaction.elasticBelowSpeed;
    return model;
}

}  // namespace corebox
