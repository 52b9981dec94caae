// Data the panels read and write. Read-only, filled by the app from the simulation (the UI never
// asks a backend itself): observable time series, speed distributions with their Maxwell-Boltzmann
// references, and performance figures. Written by the panel: the display settings (colour mode,
// steps per frame, vsync, what is shown) and the actions it requests of the frame loop.
#pragma once

#include <array>
#include <cstdint>
#include <deque>
#include <string>
#include <vector>

#include "observables.h"

namespace corebox {

class ObservableHistory {
public:
    explicit ObservableHistory(size_t capacity = 600) : m_capacity(capacity) {}
    void push(const ObservablesRow& row, double conserved0, double targetTemperature, int64_t stepsSinceLast);
    void clear();
    // A recovery went back to `time`: the points after it are dropped.
    void dropAfter(double time);

    std::vector<float> time, kinetic, potential, total, dissipated, drift, temperature, target, collisionsPerStep;
    // Averaged over the window since the previous row (pressure.h); rows with no window are skipped.
    std::vector<float> pressureWall, pressureVirial;

private:
    size_t m_capacity;
};

struct SpeedSeries {
    std::string name;
    std::array<float, 3> color{1, 1, 1};
    double mass = 1;
    // For all species together: the MB reference is the mixture sum_k weight_k f(v; m_k, T).
    std::vector<std::array<double, 2>> mixture;  // (weight, mass)
    int64_t count = 0;
    std::vector<float> density;  // histogram normalised to a probability density over speed
    double ksStatistic = 0, ksCritical = 0;
    double temperatureEquipartition = 0;  // m <v^2> / 3, from the kinetic energy
    double temperatureDistribution = 0;   // pi m <v>^2 / 8, from the mean speed of the histogram
};

struct SpeedDistributionData {
    std::vector<SpeedSeries> species;  // one per species, then "all" last
    double maxSpeed = 4;
    double targetTemperature = 0;  // 0: no thermostat
};

// The speed-vs-accuracy panel: cost (force passes per unit time) against the energy drift rate
// (|slope| of the conserved sum over the energy scale, per unit time), log-log. The study's runs of
// this scene are lines, one per method and precision; the running simulation adds one point per
// integrator setting it ran with (a live switch starts a new one).
struct AccuracySeries {
    std::string label;                         // "rk4 fp64"
    std::string method;                        // "rk4", "dp5 adaptive": the legend's entry
    bool faint = false;                        // fp32: drawn fainter than fp64 in the method's colour
    std::array<float, 3> color{1, 1, 1};
    std::vector<std::array<double, 2>> points;  // (cost, drift rate), by cost
};

struct AccuracyPoint {
    std::string label;  // "verlet fp64 dt 0.002"
    double cost = 0, driftRate = 0;
    bool running = false;  // the setting running now (its point moves as the run goes on)
};

struct SpeedAccuracyData {
    std::string studySource;  // the study file the lines come from; "" none found
    std::vector<AccuracySeries> study;
    std::vector<AccuracyPoint> live;
};

struct PerformanceData {
    std::string backend, device;
    std::string forces;  // the pair-force model in use and why (force_model.h)
    std::string integrator;  // method = "auto": what the pilot chose and why (auto_integrator.h); "" otherwise
    double stepsPerSecond = 0, framesPerSecond = 0, pairInteractionsPerSecond = 0;
    bool pairForces = true;  // false for pure hard spheres: no force pass to rate
    double msStep = 0;  // simulation steps per frame (wall clock), split into:
    double msForce = 0, msIntegrate = 0, msCollide = 0;
    double msObserve = 0, msInterop = 0, msRender = 0;
    int stepsPerFrame = 1;
};

struct DisplaySettings {
    bool colorBySpeed = false;
    int stepsPerFrame = 4;
    bool vsync = true;
    bool paused = false;
    bool showPanel = true;
    bool showHelp = false;
};

// What the panel asks the app to do this frame.
struct PanelActions {
    bool reset = false;
    bool singleStep = false;
    bool screenshot = false;
    std::string loadPreset;      // path, or ""
    std::string saveScenePath;   // path, or ""
};

}  // namespace corebox
