// Scene description: everything a run needs, as plain parameter structs with defaults and units.
// Reduced units throughout: lengths in sigma of species 0, energies in epsilon, masses in the mass
// of species 0, time tau = sigma sqrt(m / eps), k_B = 1.
//
// Creation-time settings (counts, species, box, initial conditions) restart a run; per-step ones
// (StepParameters: dt, method, precision, mixing, restitution, gravity, thermostat) apply live.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "butcher_tableau.h"
#include "pair_potential.h"
#include "vocabulary.h"  // Precision, ThermostatKind, Placement and the names of every choice

namespace corebox {

struct BoxDef {
    std::array<double, 3> size{10, 10, 10};  // box edge lengths [sigma]; walls at 0 and L per axis
    double wallRestitution = 1.0;            // e_w in [0, 1]: v_n' = -e_w v_n
};

struct SpeciesDef {
    std::string name = "A";
    int64_t count = 0;
    double mass = 1.0;      // [m]
    double radius = 0.5;    // hard-core radius a [sigma]; pairs collide at R < a_i + a_j
    double sigma = 1.0;     // LJ length [sigma]
    double epsilon = 1.0;   // LJ well depth [eps]; 0: no pair force (pure hard spheres)
    std::array<float, 3> color{0.8f, 0.3f, 0.2f};  // linear RGB in [0, 1], for the renderer
    // This species' own uniform acceleration, added to interaction.gravity [sigma / tau^2] (a balloon
    // species rising, a heavy one falling faster). The contact phase takes "up" from the global gravity.
    std::array<double, 3> acceleration{0, 0, 0};
};

struct InteractionDef {
    // x_ij, symmetric, one row per species; empty means 1 for every pair.
    std::vector<std::vector<double>> mixing;
    double cutoff = 0.0;                     // r_c [sigma]; 0: all pairs
    CutoffShift shift = CutoffShift::Force;
    double restitution = 1.0;                // particle-particle e in [0, 1]
    std::array<double, 3> gravity{0, 0, 0};  // uniform acceleration [sigma / tau^2]
    double elasticBelowSpeed = 1e-3;         // contacts slower than this are elastic [sigma / tau]
    int maxCollisionRounds = 64;             // cap on parallel resolution rounds per step
    // The largest cap a scene may set: a GPU keeps two counters a round and clears them every stage.
    static constexpr int kMaxCollisionRoundsLimit = 4096;
    // Cap on the contact phase's sweeps per listing (collision_rounds.h); 0: the backend's own (16
    // Gauss-Seidel sweeps, CPU and GPU; 128 where the GPU falls back to Jacobi sweeps). Fewer trade
    // resting accuracy for speed, as a game engine's iteration count does.
    int contactSweeps = 0;
    // Cap on the contact phase's listings per step (collision_rounds.cpp: a listing whose overlaps were
    // deeper than 2% of a diameter when it was made is listed again after its sweeps); 0: corebox's own,
    // kMaxContactListings. Fewer leave a landing's deep overlaps to the next steps, as a game engine's
    // fixed iteration budget does.
    int contactListings = 0;
    static constexpr int kMaxContactListings = 32;
    ForceModel forces = ForceModel::Auto;    // how pair forces are summed (force_model.h)
    double skin = 0.3;                       // neighbour lists: cells and lists of r_c + skin [sigma]
};

struct IntegratorDef {
    Method method = Method::Rk4;
    double dt = 1e-3;                // [tau]; the initial step when adaptive
    Precision precision = Precision::Fp64;
    bool adaptive = false;           // dp5 only: step size from the embedded error estimate
    double tolerance = 1e-8;         // adaptive: absolute and relative tolerance of the controller;
                                     // automatic: the energy error allowed per unit time [1/tau]
    // method = "auto": method, precision and dt are chosen at start by a pilot study (auto_integrator.h)
    // as the cheapest that keeps the conserved sum within `tolerance` per unit time; a simulation
    // refuses a scene whose choice has not been made.
    bool automatic = false;
};

struct ThermostatDef {
    ThermostatKind kind = ThermostatKind::Bussi;
    double temperature = 1.0;  // target kT [eps]
    double tau = 0.1;          // coupling time [tau]
};

struct InitDef {
    double temperature = 1.0;  // initial kT [eps] of the Maxwell-Boltzmann velocities
    uint64_t seed = 1;
    Placement placement = Placement::Lattice;
    std::string particlesFile;  // CSV id,species,x,y,z,vx,vy,vz; overrides placement and velocities
};

// How many GPUs run a CUDA scene and how they share positions (ignored by the CPU backend).
struct DevicesDef {
    int gpus = 0;                      // 1 .. the GPUs visible; 0: auto (the measured crossover for N)
    Exchange exchange = Exchange::Auto;
};

struct Scene {
    std::string sourcePath;  // file the scene came from ("" when built in code); names errors
    BoxDef box;
    std::vector<SpeciesDef> species;
    InteractionDef interaction;
    IntegratorDef integrator;
    ThermostatDef thermostat;
    InitDef init;
    DevicesDef devices;

    int64_t particleCount() const;
    double mixing(size_t i, size_t j) const;
};

// Everything the backend applies per step; changes take effect at the next step.
struct StepParameters {
    IntegratorDef integrator;
    InteractionDef interaction;
    BoxDef box;
    std::vector<SpeciesDef> species;  // masses, radii and LJ parameters per species
};

StepParameters stepParametersOf(const Scene& scene);

}  // namespace corebox
