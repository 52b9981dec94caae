// Scenes the benchmarks measure, shared so the force pass and the full steps describe one model, and
// so that the ball pile the benchmark builds in code is the scene assets/pile.toml loads (a unit test,
// tests/unit/test_pile_preset.cpp, holds the two equal at the preset's N).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

#include "scene.h"

namespace corebox {

// LJ particles at number density `density` whose hard cores (radius 0.56: contact at 1.12 sigma,
// near the bottom of the well) collide often at T = 1.5: the report's model of potentials plus
// hard-core collisions.
inline Scene throughputScene(int64_t n, double density, Precision precision, Method method) {
    Scene scene;
    SpeciesDef s;
    s.name = "LJ";
    s.count = n;
    s.radius = 0.56;
    scene.species = {s};
    const double box = std::cbrt(double(n) / density);
    scene.box.size = {box, box, box};
    scene.integrator.method = method;
    scene.integrator.dt = 1e-3;
    scene.integrator.precision = precision;
    scene.thermostat.kind = ThermostatKind::None;
    scene.init.temperature = 1.5;
    return scene;
}

// ---- the LJ fluid of `corebox bench md` ---------------------------------------------------------------
//
// The standard cut-off LJ benchmark (LAMMPS' bench/in.lj, HOOMD-blue's LJ benchmark) in a walled
// box: number density 0.8, T = 1.5 from a lattice, r_c = 2.5 with no shift (LAMMPS' lj/cut),
// velocity Verlet with dt = 0.002, elastic walls, no thermostat. The hard cores (radius 0.3, contact
// at 0.6 sigma) are never reached at this temperature: the steps time the force field and the walls.
struct MdParameters {
    double density = 0.8;
    double temperature = 1.5;
    double cutoff = 2.5;
    double dt = 0.002;
    double radius = 0.3;
    uint64_t seed = 12345;
};

inline constexpr MdParameters kMd{};

inline Scene mdScene(int64_t n, Precision precision, ForceModel forces) {
    Scene scene;
    SpeciesDef s;
    s.name = "LJ";
    s.count = n;
    s.radius = kMd.radius;
    scene.species = {s};
    const double box = std::cbrt(double(n) / kMd.density);
    scene.box.size = {box, box, box};
    scene.interaction.cutoff = kMd.cutoff;
    scene.interaction.shift = CutoffShift::None;
    scene.interaction.forces = forces;
    scene.integrator.method = Method::Verlet;
    scene.integrator.dt = kMd.dt;
    scene.integrator.precision = precision;
    scene.thermostat.kind = ThermostatKind::None;
    scene.init.temperature = kMd.temperature;
    scene.init.seed = kMd.seed;
    return scene;
}

// ---- the ball pile (the game programmer's scene) ---------------------------------------------------
//
// Balls dropped into a box under gravity: radius 0.5, mass 1, restitution 0.5 with each other and the
// walls, g = 9.81, a 30 x 30 x 60 box (z up, as the renderer draws it), dt = 1/240, no pair force, no
// thermostat. Lattice placement spreads the balls over the whole box, so the top layer falls ~50
// diameters and lands ~3.2 s in (sqrt(2 * 50 / 9.81)); the pile then settles in about a second.
struct PileParameters {
    double radius = 0.5;                          // [sigma]
    double mass = 1.0;                            // [m]
    double restitution = 0.5;                     // ball-ball e
    double wallRestitution = 0.5;                 // ball-wall e_w
    double gravity = 9.81;                        // along -z [sigma / tau^2]
    std::array<double, 3> box{30.0, 30.0, 60.0};  // z is the tall axis
    double dt = 1.0 / 240.0;                      // [tau]
    int maxCollisionRounds = 64;
    double initTemperature = 0.1;  // a little random motion, so the lattice does not fall as a block
    uint64_t seed = 7;
    int64_t presetCount = 10000;  // assets/pile.toml
    // Most balls the 30 x 30 x 60 box takes: a lattice spacing of ~1.07 diameters, hard-core packing
    // fraction 0.39 (packing.h refuses more than 0.45), and a pile ~36 diameters high at rest.
    int64_t fullBoxCount = 40000;
};

inline constexpr PileParameters kPile{};

// The box for n balls: 30 x 30 x 60 up to kPile.fullBoxCount balls; beyond, the horizontal edges grow
// together to 30 sqrt(n / fullBoxCount), rounded up to a tenth, keeping the height and at most that
// density, so the lattice keeps its spacing and the pile at rest its height.
inline std::array<double, 3> pileBox(int64_t n) {
    std::array<double, 3> box = kPile.box;
    if (n > kPile.fullBoxCount) {
        const double edge = std::ceil(10.0 * box[0] * std::sqrt(double(n) / double(kPile.fullBoxCount))) / 10.0;
        box[0] = box[1] = edge;
    }
    return box;
}

inline Scene pileScene(int64_t n, Precision precision) {
    Scene scene;
    scene.box.size = pileBox(n);
    scene.box.wallRestitution = kPile.wallRestitution;
    SpeciesDef ball;
    ball.name = "ball";
    ball.count = n;
    ball.mass = kPile.mass;
    ball.radius = kPile.radius;
    ball.sigma = 2 * kPile.radius;
    ball.epsilon = 0.0;  // no pair force: balls only collide
    ball.color = {float(0x3d) / 255.0f, float(0x8f) / 255.0f, float(0xd9) / 255.0f};  // "#3d8fd9"
    scene.species = {ball};
    scene.interaction.restitution = kPile.restitution;
    scene.interaction.gravity = {0.0, 0.0, -kPile.gravity};
    scene.interaction.maxCollisionRounds = kPile.maxCollisionRounds;
    scene.integrator.method = Method::Verlet;  // constant gravity: exact, and the cheapest
    scene.integrator.dt = kPile.dt;
    scene.integrator.precision = precision;
    scene.thermostat.kind = ThermostatKind::None;
    scene.init.temperature = kPile.initTemperature;
    scene.init.seed = kPile.seed;
    scene.init.placement = Placement::Lattice;
    return scene;
}


// ---- the elastic hard-sphere fluid (issue 9, item 4; assets/dense_hard_spheres.toml) ----------------
//
// N spheres of diameter 1 (radius 0.5, mass 1), restitution 1 with each other and the walls, no pair
// force, no gravity, no thermostat, kT = 1, in a cube whose edge gives the packing fraction phi over
// the whole box, N pi / (6 L^3) (the fraction packing.h limits to 0.45). The bulk is denser than
// that (no centre comes within a radius of a wall) and is measured, not assumed
// (hard_sphere_measures.h). A simple cubic lattice start (spacing 1.05 diameters at phi = 0.45)
// has no overlap; it melts within a few collision times. Verlet is exact without forces.
inline Scene hardSphereFluidScene(int64_t n, double phi, Precision precision, double dt, uint64_t seed = 1) {
    Scene scene;
    SpeciesDef sphere;
    sphere.name = "sphere";
    sphere.count = n;
    sphere.mass = 1.0;
    sphere.radius = 0.5;
    sphere.sigma = 1.0;
    sphere.epsilon = 0.0;
    scene.species = {sphere};
    // One part in 10^12 larger: the cube root and packing.h's N (4/3) pi a^3 / L^3 round differently, and
    // phi = 0.45 exactly (packing.h's limit) would otherwise be refused for some N (50000 is one).
    const double edge = std::cbrt(double(n) * 3.14159265358979323846 / (6.0 * phi)) * (1.0 + 1e-12);
    scene.box.size = {edge, edge, edge};
    scene.box.wallRestitution = 1.0;
    scene.interaction.restitution = 1.0;
    scene.integrator.method = Method::Verlet;
    scene.integrator.dt = dt;
    scene.integrator.precision = precision;
    scene.thermostat.kind = ThermostatKind::None;
    scene.init.temperature = 1.0;
    scene.init.seed = seed;
    scene.init.placement = Placement::Lattice;
    return scene;
}

}  // namespace corebox
