// `corebox bench hardspheres`: the elastic hard-sphere fluid (bench_scenes.h: hardSphereFluidScene)
// at several packing fractions, judged against theory (hard_sphere_theory.h) and timed. For each phi:
// Z from the walls (whole walls and their centres), from the whole-box virial and from the bulk's
// own virial, against Carnahan-Starling at the measured bulk packing fraction; the collision
// frequency per particle in the bulk against Enskog; the energy drift; steps per second and
// collisions per particle per step. Writes PREFIX.csv (one row per phi) and PREFIX.json (with the
// hardware, the command and the method), and progress lines on stderr every ~2 s.
//
// Design note. Measuring and timing share one run: steps are timed alone (the backend finished),
// while the state downloads that the bulk measures need (hard_sphere_measures.h: a step sampled is
// one with its state before and after) are outside the timed region. A run that blows up is
// recorded (outcome, message) and the benchmark goes on with the next phi, as `bench pile` does.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "scene.h"

namespace corebox {

struct HardSphereBenchmarkOptions {
    std::string backend = "cpu";  // cpu | cuda | auto
    int threads = 0;              // CPU threads; 0: all cores
    int64_t n = 0;                // spheres; 0: 2000 on the CPU, 50,000 on CUDA
    std::vector<double> packingFractions{0.2, 0.35, 0.45};  // over the whole box, N pi / (6 L^3)
    Precision precision = Precision::Fp64;
    int64_t steps = 0;                 // measured steps per phi; 0: 8 tau worth
    double equilibrate = 2.0;          // simulated time before measuring [tau]
    double collisionsPerStep = 0.02;   // sets dt from Enskog's rate at the box's phi
    int sampleEvery = 0;               // bulk sample every K steps; 0: 1 on the CPU, 10 on CUDA
    // Bulk region: diameters inside the region open to centres; 0: 3 below phi = 0.4, 5 from it (the
    // walls' layering reaches further in a denser fluid: at phi 0.45 a margin of 3 still held part of it).
    double margin = 0;
    uint64_t seed = 1;
    std::string outputPrefix;          // writes PREFIX.csv and PREFIX.json; "": CSV on stdout only
    std::string commandLine;
};

struct HardSphereRunResult {
    std::string backend, device, precision;
    int threads = 0;
    int64_t n = 0;
    double phi = 0;  // over the box
    double box = 0, dt = 0, equilibrate = 0;
    int64_t steps = 0;
    double measuredTime = 0;
    double margin = 0;  // of the bulk region, diameters
    double phiBulk = 0, densityBulk = 0, temperatureBulk = 0, temperature = 0;
    double zCs = 0;
    double zWall = 0, zWallCentre = 0, zVirial = 0, zBulkVirial = 0;
    double pressureWall = 0, pressureWallCentre = 0, pressureVirial = 0, pressureBulkVirial = 0;
    double rateBulk = 0, rateEnskog = 0;  // collisions per particle per unit time
    double rateBox = 0;                   // 2 x pair collisions / (N t) over the whole box
    double energyDrift = 0;               // (K_end - K_start) / K_start over the measurement
    double dissipatedRelative = 0;        // what the contact phase took, over K_start
    double stepsPerSecond = 0;
    double collisionsPerParticleStep = 0;  // pair collisions x 2 / (N steps)
    int64_t roundCapHits = 0;
    int maxRounds = 0;
    std::string outcome, message;
};

std::vector<HardSphereRunResult> runHardSphereBenchmark(const HardSphereBenchmarkOptions& options);

}  // namespace corebox
