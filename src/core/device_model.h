// The constants a backend needs to run the model, derived once on the host from the scene's step
// parameters (DESIGN.md sec. 2): the species-pair coefficient table, per-species masses and radii,
// the box, gravity and the collision settings. Backends convert them to their precision; none of
// them derives anything from a Scene itself, so every backend runs exactly the same model.
#pragma once

#include <vector>

#include "pair_potential.h"
#include "scene.h"
#include "vec3.h"

namespace corebox {

struct DeviceModel {
    std::vector<PairCoefficients<double>> pairs;  // S x S, row-major (pair_table.h)
    std::vector<double> mass;                     // per species [m]
    std::vector<double> radius;                   // hard-core radius per species [sigma]
    Vec3<double> box{1, 1, 1};                    // edge lengths [sigma]; walls at 0 and L
    Vec3<double> gravity{0, 0, 0};                // uniform acceleration [sigma / tau^2]; "up" of the contact phase
    std::vector<Vec3<double>> acceleration;       // per species: gravity plus the species' own [sigma / tau^2]
    double restitution = 1.0;                     // particle-particle e
    double wallRestitution = 1.0;                 // e_w
    double elasticBelowSpeed = 1e-3;              // contacts slower than this are elastic [sigma / tau]
    bool anyPairForce = true;                     // false: pure hard spheres, no force pass needed
    bool hasCutoff = false;                       // pairs beyond r_c contribute nothing
    double cutoff = 0;                            // r_c [sigma], one for every pair; 0: none
    // How the pair forces are summed (force_model.h); deviceModelOf leaves all pairs, the simulation
    // sets the resolved choice. Neighbour lists reach cutoff + skin.
    ForceModel forces = ForceModel::AllPairs;
    double skin = 0.3;                            // [sigma]

    int speciesCount() const { return int(mass.size()); }
    double maxRadius() const;
    double smallestContact() const;  // 2 a of the smallest radius a > 0; 0 when every radius is 0
};

DeviceModel deviceModelOf(const StepParameters& parameters);

}  // namespace corebox
