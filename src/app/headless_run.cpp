// The headless frame loop (`corebox run SCENE --headless`): frames rendered on an EGL context and
// written as PNG (and video) by a FrameDumper, optionally with the panels drawn in as a HUD.
#include <chrono>
#include <cstdio>

#include "errors.h"
#include "frame_dumper.h"
#include "imgui_layer.h"
#include "interruption.h"
#include "panels.h"
#include "particle_renderer.h"
#include "platform_error.h"
#include "progress.h"
#include "rendered_run.h"
#include "scene_drawing.h"
#include "state_csv.h"

namespace corebox {
namespace {

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t) { return 1e3 * std::chrono::duration<double>(Clock::now() - t).count(); }

// Frame timings and where the frames are (and the video, closed here), on stderr.
void reportFrames(const RunOptions& options, FrameDumper& frames) {
    const bool videoOk = frames.finish();
    const FrameTimings& t = frames.timings();
    const double n = double(std::max<int64_t>(t.frames, 1));
    const double fps = t.wall > 0 ? double(t.frames - 1) / t.wall : 0.0;  // intervals between the first and the last frame
    if (!options.quiet && !options.headless.writePng)
        std::fprintf(stderr, "[corebox] %lld frames rendered, no PNG written: %.1f frames/s including simulation; per frame %.2f ms render, %.2f ms read-back\n",
                     (long long)t.frames, fps, 1e3 * t.render / n, 1e3 * t.readback / n);
    else if (!options.quiet)
        std::fprintf(stderr,
                 "[corebox] %lld frames in %s/ (frame_000000.png ...): %.1f frames/s including simulation and output; per frame "
                 "%.1f ms render, %.1f ms read-back, %.1f ms waiting for PNG encoding (%d encoder threads)\n",
                 (long long)t.frames, options.headless.outDir.c_str(), fps, 1e3 * t.render / n,
                 1e3 * t.readback / n, 1e3 * t.encodeWait / n, t.encoders);
    if (!options.headless.videoPath.empty()) {
        if (videoOk) std::fprintf(stderr, "[corebox] video written to %s\n", options.headless.videoPath.c_str());
        else throw InputError("--video: ffmpeg failed to write " + options.headless.videoPath);
    } else if (!options.quiet && options.headless.writePng) {
        std::fprintf(stderr, "[corebox] make a video with: ffmpeg -framerate 30 -i %s/frame_%%06d.png -pix_fmt yuv420p %s/movie.mp4\n",
                     options.headless.outDir.c_str(), options.headless.outDir.c_str());
    }
}

// An EGL context on the GPU that runs the simulation (for interop), else on any device.
std::unique_ptr<FrameDumper> openFrameDumper(FrameDumpOptions dump, const std::array<float, 3>& box) {
    try {
        return std::make_unique<FrameDumper>(dump, box);
    } catch (const PlatformError& e) {
        if (dump.context.cudaDevice < 0) throw;
        std::fprintf(stderr, "[corebox] warning: %s; rendering on another EGL device without interop\n", e.what());
        dump.context.cudaDevice = -1;
        return std::make_unique<FrameDumper>(dump, box);
    }
}

}  // namespace

int runHeadlessFrames(const RunOptions& options, const Scene& scene) {
    const HeadlessOptions& h = options.headless;
    std::unique_ptr<LiveRun> livePtr;
    return runRendered(options, livePtr, [&] {
        livePtr = std::make_unique<LiveRun>(scene, BackendChoice{options.backend.name, scene.integrator.precision, options.backend.threads, 0},
                                            liveRunOptions(options, h.stepsPerFrame));
        LiveRun& live = *livePtr;
        live.display().colorBySpeed = h.colorBy == ColorMode::Speed;
        live.display().stepsPerFrame = int(h.stepsPerFrame);
        FrameDumpOptions dump;
        dump.outDir = h.outDir;
        dump.width = h.size.width;
        dump.height = h.size.height;
        dump.videoPath = h.videoPath;
        dump.writePng = h.writePng;
        dump.context.softwareOnly = h.softwareOnly;
        dump.context.cudaDevice = h.softwareOnly ? -1 : live.simulation().backend().interopDevice();
        const std::array<float, 3> box{float(scene.box.size[0]), float(scene.box.size[1]), float(scene.box.size[2])};
        const std::unique_ptr<FrameDumper> frames = openFrameDumper(dump, box);
        std::unique_ptr<ImGuiLayer> hud;
        if (h.hud) hud = std::make_unique<ImGuiLayer>(nullptr, "");
        LiveFeed feed;
        if (!options.quiet) std::fprintf(stderr, "[corebox] headless rendering on %s\n", frames->contextDescription().c_str());
        ProgressReporter progress((h.frames - 1) * h.stepsPerFrame, !options.quiet);
        auto overlay = [&](int w, int hgt) {
            live.refreshSpeedDistributions();
            hud->beginFrame(w, hgt, 1.0 / 30.0);
            drawHud(live.speeds(), live.history(), live.performance(), float(w), float(hgt),
                    ParticleRenderer::legendBottomHeight(h.colorBy, hgt));
            hud->endFrame();
        };
        auto render = [&](int64_t index) {
            Clock::time_point t = Clock::now();
            feed.update(live, frames->renderer());
            const double msFeed = msSince(t);
            t = Clock::now();
            frames->writeFrame(index, liveRenderStyle(live), hud ? std::function<void(int, int)>(overlay) : std::function<void(int, int)>());
            live.recordFrame(msFeed, msSince(t));
        };
        render(0);
        for (int64_t f = 1; f < h.frames; ++f) {
            const ScriptEffects e = live.advance(live.display().paused ? 0 : live.display().stepsPerFrame);
            if (e.reset) live.reset();
            render(f);
            if (!e.screenshotPath.empty()) {
                writeOutputPng(e.screenshotPath, frames->lastImage());
                std::fprintf(stderr, "[corebox] screenshot written to %s\n", e.screenshotPath.c_str());
            }
            progress.update(live.simulation().stepIndex(), live.simulation().time(), live.history().temperature.empty() ? 0.0 : live.history().temperature.back());
            if (e.quit || interruptRequested()) break;  // the frame of the current state is drawn
        }
        if (!options.screenshotPath.empty()) writeOutputPng(options.screenshotPath, frames->lastImage());
        finishLiveRun(options, live);
        reportFrames(options, *frames);
    });
}

}  // namespace corebox
