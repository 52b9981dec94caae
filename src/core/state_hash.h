// A 64-bit FNV-1a hash of a state's exact bits (positions, velocities, species): the determinism
// tests and run logs compare runs by it.
#pragma once

#include <cstdint>
#include <cstring>

#include "particle_state.h"

namespace corebox {

inline uint64_t stateHash(const ParticleState& state) {
    uint64_t h = 1469598103934665603ull;
    auto mix = [&h](const void* data, size_t bytes) {
        const unsigned char* p = static_cast<const unsigned char*>(data);
        for (size_t k = 0; k < bytes; ++k) {
            h ^= p[k];
            h *= 1099511628211ull;
        }
    };
    mix(state.position.data(), state.position.size() * sizeof(Vec3<double>));
    mix(state.velocity.data(), state.velocity.size() * sizeof(Vec3<double>));
    mix(state.species.data(), state.species.size() * sizeof(int32_t));
    return h;
}

}  // namespace corebox
