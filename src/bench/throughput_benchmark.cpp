#include "throughput_benchmark.h"

#include "bench_scenes.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "atomic_file.h"
#include "backend_factory.h"
#include "egl_headless_context.h"
#include "force_pass.h"
#include "hardware_info.h"
#include "initial_conditions.h"
#include "instance_feed.h"
#include "offscreen_target.h"
#include "particle_renderer.h"
#include "scene_drawing.h"
#include "simulation.h"

namespace corebox {
namespace {

using Clock = std::chrono::steady_clock;
double seconds(Clock::time_point since) { return std::chrono::duration<double>(Clock::now() - since).count(); }

struct Record {
    std::string kind;  // force_pass | step | frame
    std::string precision, method;
    int64_t n = 0;
    double value = 0;  // pairs/s, ms/step, ms/frame
    std::string unit;
    double extra = 0;  // steps/s, collisions/step, frames/s
    std::string extraUnit;
};

void forcePass(const ThroughputOptions& o, Precision p, int64_t n, std::vector<Record>& out) {
    const Scene scene = throughputScene(n, 0.5, p, Method::Rk4);
    const std::unique_ptr<Backend> backend = forcePassBackend(BackendChoice{o.backend, p, 0, 0}, scene);
    runForcePass(*backend, n);  // warm-up
    const Clock::time_point start = Clock::now();
    int64_t pairs = 0;
    double t = 0;
    do {
        pairs += runForcePass(*backend, n);
        t = seconds(start);
    } while (t < o.minSeconds);
    out.push_back({"force_pass", precisionName(p), "", n, double(pairs) / t, "pair_interactions_per_second", 0, ""});
    std::fprintf(stderr, "[corebox] force pass %s N = %lld: %.3e pair interactions/s\n", precisionName(p), (long long)n, double(pairs) / t);
}

void fullStep(const ThroughputOptions& o, Precision p, Method m, std::vector<Record>& out) {
    const Scene scene = throughputScene(o.stepN, 0.5, p, m);
    SimulationLimits limits;
    limits.maxEnergyDrift = 1e9;  // timing only
    Simulation sim(scene, makeBackend(BackendChoice{o.backend, p, 0, 0}), makeInitialState(scene), limits);
    for (int s = 0; s < 3; ++s) sim.step();
    const Clock::time_point start = Clock::now();
    int64_t steps = 0, collisions = 0;
    double t = 0;
    do {
        const StepReport r = sim.step();
        collisions += r.pairCollisions + r.wallCollisions;
        ++steps;
        t = seconds(start);
    } while (t < o.minSeconds || steps < 5);
    const double ms = 1e3 * t / double(steps);
    out.push_back({"step", precisionName(p), methodName(m), o.stepN, ms, "ms_per_step", double(collisions) / double(steps), "collisions_per_step"});
    std::fprintf(stderr, "[corebox] full step %s %s N = %lld: %.3f ms (%.0f collisions per step)\n", precisionName(p), methodName(m),
                 (long long)o.stepN, ms, double(collisions) / double(steps));
}

void frames(const ThroughputOptions& o, std::vector<Record>& out) {
    Scene scene = throughputScene(o.frameN, 0.1, Precision::Fp32, Method::Verlet);
    scene.species[0].epsilon = 0;  // hard spheres: the frame, not the force pass, is measured here
    Simulation sim(scene, makeBackend(BackendChoice{o.backend, Precision::Fp32, 0, 0}), makeInitialState(scene));
    EglHeadlessContext context(HeadlessContextOptions{sim.backend().interopDevice(), false});
    ParticleRenderer renderer;
    OffscreenTarget target(o.frameWidth, o.frameHeight);
    InstanceFeed feed(sim, renderer, ColorMode::Speed);
    OrbitCamera camera;
    const std::array<float, 3> box{float(scene.box.size[0]), float(scene.box.size[1]), float(scene.box.size[2])};
    camera.frameBox({box[0], box[1], box[2]}, float(o.frameWidth) / float(o.frameHeight));
    const RenderStyle style = renderStyleFor(scene, ColorMode::Speed);
    std::vector<uint8_t> pixels;
    double fill = 0, render = 0, readback = 0;
    int count = 0;
    for (int k = 0; k < 3 + 30; ++k) {
        sim.step();
        Clock::time_point t = Clock::now();
        feed.update();
        const double f = seconds(t);
        t = Clock::now();
        target.bind();
        renderer.render(camera, box, style, o.frameWidth, o.frameHeight);
        glFinish();
        const double r = seconds(t);
        t = Clock::now();
        target.readPixels(pixels);
        const double b = seconds(t);
        if (k >= 3) {  // warm-up frames excluded
            fill += f;
            render += r;
            readback += b;
            ++count;
        }
    }
    const std::string path = feed.usesInterop() ? "interop" : "upload";
    out.push_back({"frame", "fp32", path + "_fill", o.frameN, 1e3 * fill / count, "ms_per_frame", 0, ""});
    out.push_back({"frame", "fp32", "render", o.frameN, 1e3 * render / count, "ms_per_frame", count / (fill + render), "frames_per_second"});
    out.push_back({"frame", "fp32", "readback", o.frameN, 1e3 * readback / count, "ms_per_frame", count / (fill + render + readback),
                   "frames_per_second_with_readback"});
    std::fprintf(stderr, "[corebox] frames N = %lld at %dx%d on %s: %s %.2f ms, render %.2f ms, read-back %.2f ms: %.1f frames/s (%.1f with read-back)\n",
                 (long long)o.frameN, o.frameWidth, o.frameHeight, context.description().c_str(), path.c_str(), 1e3 * fill / count,
                 1e3 * render / count, 1e3 * readback / count, count / (fill + render), count / (fill + render + readback));
}

}  // namespace

void runThroughputBenchmark(const ThroughputOptions& o) {
    std::vector<Record> records;
    std::string device;
    {
        std::unique_ptr<Backend> probe = makeBackend(BackendChoice{o.backend, Precision::Fp32, 0, 0});
        device = probe->deviceName();
    }
    for (Precision p : o.precisions)
        for (int64_t n : o.forceSizes) forcePass(o, p, n, records);
    for (Precision p : o.precisions)
        for (Method m : o.methods) fullStep(o, p, m, records);
    if (o.frameN > 0) {
        try {
            frames(o, records);
        } catch (const std::exception& e) {
            std::fprintf(stderr, "[corebox] frame measurements skipped: %s\n", e.what());
        }
    }
    const HardwareInfo host = hostHardware();
    nlohmann::json json;
    json["benchmark"] = "throughput";
    json["command"] = o.commandLine;
    json["timestamp"] = utcTimestamp();
    json["backend"] = o.backend;
    json["device"] = device;
    json["host"] = {{"cpu", host.cpuModel}, {"hardware_threads", host.hardwareThreads}};
    json["model"] = "Lennard-Jones, one species, all pairs; steps with hard cores of radius 0.56 at number density 0.5, T = 1.5, dt = 1e-3";
    std::string csv = "kind,backend,device,precision,method,n,value,unit,extra,extra_unit\n";
    for (const Record& r : records) {
        json["results"].push_back({{"kind", r.kind}, {"precision", r.precision}, {"method", r.method}, {"n", r.n}, {"value", r.value},
                                   {"unit", r.unit}, {"extra", r.extra}, {"extra_unit", r.extraUnit}});
        char line[512];
        std::snprintf(line, sizeof line, "%s,%s,\"%s\",%s,%s,%lld,%.6g,%s,%.6g,%s\n", r.kind.c_str(), o.backend.c_str(), device.c_str(),
                      r.precision.c_str(), r.method.c_str(), (long long)r.n, r.value, r.unit.c_str(), r.extra, r.extraUnit.c_str());
        csv += line;
    }
    std::cout << csv;
    if (o.outputPrefix.empty()) return;
    AtomicFile csvFile(o.outputPrefix + ".csv");
    csvFile.stream() << "# " << o.commandLine << "\n" << csv;
    csvFile.commit();
    AtomicFile jsonFile(o.outputPrefix + ".json");
    jsonFile.stream() << json.dump(2) << "\n";
    jsonFile.commit();
}

}  // namespace corebox
