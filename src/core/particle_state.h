// Host-side particle state, always in double whatever the backend's precision: the exchange format
// between initial conditions, backends, CSV files and checkpoints. Particle i has id i.
#pragma once

#include <cstdint>
#include <vector>

#include "vec3.h"

namespace corebox {

struct ParticleState {
    std::vector<Vec3<double>> position;
    std::vector<Vec3<double>> velocity;
    std::vector<int32_t> species;

    size_t size() const { return position.size(); }
    void resize(size_t n) {
        position.resize(n);
        velocity.resize(n);
        species.resize(n);
    }
};

}  // namespace corebox
