#include "hard_sphere_benchmark.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "atomic_file.h"
#include "backend_factory.h"
#include "bench_scenes.h"
#include "errors.h"
#include "hard_sphere_measures.h"
#include "hard_sphere_theory.h"
#include "hardware_info.h"
#include "initial_conditions.h"
#include "pressure.h"
#include "simulation.h"

namespace corebox {
namespace {

using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

constexpr double kPi = 3.14159265358979323846;
constexpr double kDefaultMeasureTime = 8.0;  // tau, when --steps is not given
constexpr int kEquilibrationStretches = 8;   // velocities redrawn before each

std::string csvQuote(const std::string& text) {
    std::string out = "\"";
    for (char c : text) out += c == '"' ? std::string("\"\"") : std::string(1, c);
    return out + "\"";
}

HardSphereRunResult runOne(const HardSphereBenchmarkOptions& o, const std::string& backend, double phi) {
    HardSphereRunResult r;
    r.backend = backend;
    r.precision = precisionName(o.precision);
    r.threads = o.threads > 0 ? o.threads : hostHardware().hardwareThreads;
    r.n = o.n;
    r.phi = phi;
    r.dt = o.collisionsPerStep / enskogCollisionFrequency(6 * phi / kPi, 1.0, 1.0, 1.0);
    r.equilibrate = o.equilibrate;
    const Scene scene = hardSphereFluidScene(o.n, phi, o.precision, r.dt, o.seed);
    r.box = scene.box.size[0];
    r.steps = o.steps > 0 ? o.steps : std::llround(kDefaultMeasureTime / r.dt);
    const int sampleEvery = o.sampleEvery > 0 ? o.sampleEvery : (backend == "cpu" ? 1 : 10);
    std::unique_ptr<Simulation> sim;
    try {
        // Isothermal equilibration (hard_sphere_measures.h): stretches with velocities redrawn before each.
        int stretch = 0;
        sim = equilibrateIsothermally(scene, makeInitialState(scene), o.equilibrate, kEquilibrationStretches,
                                      [&](const Scene& sc, const ParticleState& st) {
                                          std::fprintf(stderr, "[corebox] bench hardspheres: phi %.3g, N = %lld: equilibrating, stretch %d of %d\n",
                                                       phi, (long long)o.n, ++stretch, kEquilibrationStretches);
                                          return std::make_unique<Simulation>(
                                              sc, makeBackend(BackendChoice{backend, o.precision, o.threads, 0}), st);
                                      });
        r.device = sim->backend().deviceName();
        Clock::time_point lastProgress = Clock::now();
        const ObservablesRow start = sim->observe();  // opens the pressure window
        r.margin = o.margin > 0 ? o.margin : (phi < 0.4 ? 3.0 : 5.0);
        BulkSampler bulk{bulkRegionOf(scene.box.size, 0.5, r.margin)};
        double stepSeconds = 0;
        int64_t pairs = 0;
        ParticleState before;
        bool haveBefore = false;
        for (int64_t s = 0; s < r.steps; ++s) {
            const bool sampled = s % sampleEvery == 0;
            if (sampled && !haveBefore) before = sim->state();
            sim->backend().finish();
            const Clock::time_point t0 = Clock::now();
            const StepReport report = sim->step();
            sim->backend().finish();
            stepSeconds += secondsSince(t0);
            pairs += report.pairCollisions;
            r.maxRounds = std::max(r.maxRounds, report.rounds);
            haveBefore = false;
            if (sampled) {
                ParticleState after = sim->state();
                bulk.sampleStep(before, after, report.dt);
                if ((s / sampleEvery) % 10 == 0) bulk.sampleDensity(after);
                if (sampleEvery == 1) {
                    before = std::move(after);
                    haveBefore = true;
                }
            }
            if (secondsSince(lastProgress) > 2.0) {
                lastProgress = Clock::now();
                std::fprintf(stderr, "[corebox] bench hardspheres: phi %.3g, N = %lld: step %lld of %lld, %.1f steps/s\n", phi,
                             (long long)o.n, (long long)s + 1, (long long)r.steps, double(s + 1) / std::max(stepSeconds, 1e-9));
            }
        }
        const ObservablesRow end = sim->observe();
        r.measuredTime = end.window;
        r.temperature = 2 * end.kinetic / (3.0 * double(o.n));
        r.densityBulk = bulk.density();
        r.temperatureBulk = bulk.temperature();
        r.phiBulk = packingFractionOf(r.densityBulk, 1.0);
        r.zCs = carnahanStarlingZ(r.phiBulk);
        const double nkT = r.densityBulk * r.temperatureBulk;
        r.pressureWall = end.pressureWall;
        r.pressureWallCentre = end.pressureWallCentre;
        r.pressureVirial = end.pressureVirial;
        r.pressureBulkVirial = bulk.virialPressure();
        if (nkT > 0) {
            r.zWall = r.pressureWall / nkT;
            r.zWallCentre = r.pressureWallCentre / nkT;
            r.zVirial = r.pressureVirial / nkT;
            r.zBulkVirial = r.pressureBulkVirial / nkT;
        }
        r.rateBulk = bulk.collisionFrequency();
        r.rateEnskog = enskogCollisionFrequency(r.densityBulk, 1.0, r.temperatureBulk, 1.0);
        r.rateBox = r.measuredTime > 0 ? 2.0 * double(pairs) / (double(o.n) * r.measuredTime) : 0.0;
        r.energyDrift = (end.kinetic - start.kinetic) / start.kinetic;
        r.dissipatedRelative = (end.dissipated - start.dissipated) / start.kinetic;
        r.stepsPerSecond = stepSeconds > 0 ? double(r.steps) / stepSeconds : 0.0;
        r.collisionsPerParticleStep = 2.0 * double(pairs) / (double(o.n) * double(r.steps));
        r.outcome = "ok";
    } catch (const InstabilityError& e) {
        r.outcome = "instability";
        r.message = e.what();
    } catch (const DeviceError& e) {
        r.outcome = "device_error";
        r.message = e.what();
    }
    if (sim) r.roundCapHits = sim->roundCapHits();
    return r;
}

const char* const kCsvHeader =
    "backend,device,precision,threads,n,phi,box,dt,equilibrate,steps,measured_time,margin,phi_bulk,density_bulk,temperature_bulk,"
    "temperature,z_cs,z_wall,z_wall_centre,z_virial,z_bulk_virial,pressure_wall,pressure_wall_centre,pressure_virial,"
    "pressure_bulk_virial,rate_bulk,rate_enskog,rate_box,energy_drift,dissipated_relative,steps_per_second,"
    "collisions_per_particle_step,round_cap_hits,max_rounds,outcome,message\n";

std::string csvRow(const HardSphereRunResult& r) {
    char line[2048];
    std::snprintf(line, sizeof line,
                  "%s,%s,%s,%d,%lld,%.4g,%.6g,%.6g,%.4g,%lld,%.6g,%g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,"
                  "%.6g,%.6g,%.6g,%.3e,%.3e,%.4g,%.5g,%lld,%d,%s,",
                  r.backend.c_str(), csvQuote(r.device).c_str(), r.precision.c_str(), r.threads, (long long)r.n, r.phi, r.box, r.dt,
                  r.equilibrate, (long long)r.steps, r.measuredTime, r.margin, r.phiBulk, r.densityBulk, r.temperatureBulk, r.temperature, r.zCs,
                  r.zWall, r.zWallCentre, r.zVirial, r.zBulkVirial, r.pressureWall, r.pressureWallCentre, r.pressureVirial,
                  r.pressureBulkVirial, r.rateBulk, r.rateEnskog, r.rateBox, r.energyDrift, r.dissipatedRelative, r.stepsPerSecond,
                  r.collisionsPerParticleStep, (long long)r.roundCapHits, r.maxRounds, r.outcome.c_str());
    return line + csvQuote(r.message) + "\n";
}

nlohmann::json resultJson(const HardSphereRunResult& r) {
    return {{"backend", r.backend}, {"device", r.device}, {"precision", r.precision}, {"threads", r.threads}, {"n", r.n},
            {"phi", r.phi}, {"box", r.box}, {"dt", r.dt}, {"equilibrate", r.equilibrate}, {"steps", r.steps},
            {"measured_time", r.measuredTime}, {"margin", r.margin}, {"phi_bulk", r.phiBulk}, {"density_bulk", r.densityBulk},
            {"temperature_bulk", r.temperatureBulk}, {"temperature", r.temperature}, {"z_cs", r.zCs}, {"z_wall", r.zWall},
            {"z_wall_centre", r.zWallCentre}, {"z_virial", r.zVirial}, {"z_bulk_virial", r.zBulkVirial},
            {"pressure_wall", r.pressureWall}, {"pressure_wall_centre", r.pressureWallCentre}, {"pressure_virial", r.pressureVirial},
            {"pressure_bulk_virial", r.pressureBulkVirial}, {"rate_bulk", r.rateBulk}, {"rate_enskog", r.rateEnskog},
            {"rate_box", r.rateBox}, {"energy_drift", r.energyDrift}, {"dissipated_relative", r.dissipatedRelative},
            {"steps_per_second", r.stepsPerSecond}, {"collisions_per_particle_step", r.collisionsPerParticleStep},
            {"round_cap_hits", r.roundCapHits}, {"max_rounds", r.maxRounds}, {"outcome", r.outcome}, {"message", r.message}};
}

nlohmann::json methodJson(const HardSphereBenchmarkOptions& o) {
    return {{"equilibration", "the time --equilibrate in " + std::to_string(kEquilibrationStretches) +
                                  " stretches, every velocity redrawn from Maxwell-Boltzmann (kT = 1) before each, so that the density "
                                  "settles isothermally; measured without"},
            {"scene", "N spheres of diameter 1, mass 1, restitution 1 (walls too), no pair force, no gravity, no thermostat, kT = 1, "
                      "simple cubic lattice start, velocity Verlet; cubic box with N pi / (6 L^3) = phi"},
            {"dt", "collisions_per_step / Enskog frequency at the box's phi"},
            {"collisions_per_step", o.collisionsPerStep},
            {"equilibrate", o.equilibrate},
            {"bulk", "cube `margin` diameters inside the region open to centres [a, L - a]^3: density, "
                     "temperature, collision frequency (-ln(1 - fraction of particles whose velocity changed in a step) / dt) and "
                     "virial pressure (sigma sum m |dv| / (6 V t) + kinetic) from state samples"},
            {"z", "P / (n_bulk kT_bulk); Carnahan-Starling at phi_bulk"},
            {"pressure_wall", "momentum to the six walls / (area of the faces of [a, L-a]^3 x time): includes the edges' surface stress"},
            {"pressure_wall_centre", "the same over the centre quarter of each wall: the bulk pressure"},
            {"pressure_virial", "(2 <K> + sum r_ij . J_ij / t) / (3 (L - 2a)^3), whole box"},
            {"rate_enskog", "4 n sigma^2 sqrt(pi kT / m) g(sigma), g = (1 - phi/2) / (1 - phi)^3, at the bulk density and temperature"},
            {"energy_drift", "relative change of the kinetic energy over the measurement"},
            {"steps_per_second", "measured steps over their wall time, backend finished, state downloads excluded"}};
}

}  // namespace

std::vector<HardSphereRunResult> runHardSphereBenchmark(const HardSphereBenchmarkOptions& options) {
    HardSphereBenchmarkOptions o = options;
    const std::string backend = o.backend == "auto" ? (cudaAvailable() ? "cuda" : "cpu") : o.backend;
    if (backend != "cpu" && backend != "cuda") throw InputError("--backend: unknown backend '" + o.backend + "'");
    if (o.n == 0) o.n = backend == "cpu" ? 2000 : 50000;
    if (o.n < 8) throw InputError("--n: at least 8 spheres, not " + std::to_string(o.n));
    for (double phi : o.packingFractions) {
        if (!(phi > 0 && phi <= 0.45)) throw InputError("--phi: packing fractions in (0, 0.45] (packing.h), not " + std::to_string(phi));
    }
    if (!(o.collisionsPerStep > 0)) throw InputError("--collisions-per-step: must be > 0");
    if (!(o.equilibrate >= 0)) throw InputError("--equilibrate: must be >= 0");
    if (!o.outputPrefix.empty()) AtomicFile probe(o.outputPrefix + ".json");  // an unwritable --out fails now

    std::vector<HardSphereRunResult> results;
    for (double phi : o.packingFractions) {
        results.push_back(runOne(o, backend, phi));
        const HardSphereRunResult& r = results.back();
        std::fprintf(stderr,
                     "[corebox] bench hardspheres: phi %.3g (bulk %.4f), N = %lld: Z walls' centres %.4f, bulk virial %.4f, CS %.4f; "
                     "collision rate / Enskog %.4f; energy drift %.1e; %.1f steps/s; %s\n",
                     r.phi, r.phiBulk, (long long)r.n, r.zWallCentre, r.zBulkVirial, r.zCs, r.rateEnskog > 0 ? r.rateBulk / r.rateEnskog : 0.0,
                     r.energyDrift, r.stepsPerSecond, r.outcome.c_str());
        if (r.outcome != "ok") std::fprintf(stderr, "[corebox]   %s\n", r.message.c_str());
    }

    std::string csv = kCsvHeader;
    for (const HardSphereRunResult& r : results) csv += csvRow(r);
    std::cout << csv;
    if (o.outputPrefix.empty()) return results;
    const HardwareInfo host = hostHardware();
    nlohmann::json json;
    json["benchmark"] = "hardspheres";
    json["command"] = o.commandLine;
    json["timestamp"] = utcTimestamp();
    json["backend"] = backend;
    json["device"] = results.empty() ? "" : results.front().device;
    json["precision"] = precisionName(o.precision);
    json["n"] = o.n;
    json["host"] = {{"cpu", host.cpuModel}, {"hardware_threads", host.hardwareThreads}, {"name", host.hostName}};
    json["method"] = methodJson(o);
    json["results"] = nlohmann::json::array();
    for (const HardSphereRunResult& r : results) json["results"].push_back(resultJson(r));
    AtomicFile csvFile(o.outputPrefix + ".csv");
    AtomicFile jsonFile(o.outputPrefix + ".json");
    csvFile.stream() << "# " << o.commandLine << "\n" << csv;
    jsonFile.stream() << json.dump(2) << "\n";
    csvFile.commit();
    jsonFile.commit();
    std::fprintf(stderr, "[corebox] wrote %s.csv and %s.json\n", o.outputPrefix.c_str(), o.outputPrefix.c_str());
    return results;
}

}  // namespace corebox
