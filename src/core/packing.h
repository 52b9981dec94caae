// Whether the hard cores of a scene fit in its box: one rule, used by scene validation
// (scene_validation.cpp) and by the initial placement (initial_conditions.cpp), so that a scene
// that validates can be placed and a scene that is refused could not have been.
//
//  1. Every core fits the box: 2 a_s <= the smallest edge, for every species.
//  2. The hard-core packing fraction sum_s N_s (4/3) pi a_s^3 / V is at most kMaxPackingFraction.
//     Above ~0.45 random placement stalls and a simple cubic lattice (at most 0.52) barely fits;
//     such a scene is a typo in a count or a box size far more often than an intent.
//  3. With lattice placement (and no particle file), the lattice that placement uses,
//     latticeSites(), has a spacing on every axis of at least the largest contact distance
//     a_i + a_j among the species present.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>

#include "scene.h"

namespace corebox {

constexpr double kMaxPackingFraction = 0.45;

struct PackingProblem {
    std::string key;      // "species[i].radius" (rule 1) or "species" (rules 2 and 3)
    std::string message;  // "more particles than fit: ..." for rules 2 and 3
};

// The first rule the scene breaks, or nothing when its particles fit.
std::optional<PackingProblem> packingProblem(const Scene& scene);

// Sites per axis of the simple cubic lattice for the scene's particles: about as many per unit
// length on every axis, grown on the axis of widest spacing until every particle has a site.
std::array<int64_t, 3> latticeSites(const Scene& scene);

}  // namespace corebox
