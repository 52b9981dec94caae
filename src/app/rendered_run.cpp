#include "rendered_run.h"

#include <epoxy/gl.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <imgui.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <glob.h>

#include "errors.h"
#include "frame_dumper.h"
#include "gl_program.h"
#include "glfw_window.h"
#include "imgui_layer.h"
#include "instance_feed.h"
#include "live_run.h"
#include "panels.h"
#include "progress.h"
#include "scene_io.h"
#include "scene_view.h"
#include "state_csv.h"
#include "ui_settings_file.h"

namespace corebox {
namespace {

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t) { return 1e3 * std::chrono::duration<double>(Clock::now() - t).count(); }

LiveRunOptions liveOptions(const RunOptions& options, int64_t observeEvery) {
    LiveRunOptions live;
    live.observeEvery = std::max<int64_t>(1, observeEvery);
    live.observablesPath = options.observablesPath;
    if (!options.scriptPath.empty()) live.script = Script::load(options.scriptPath);
    return live;
}

// The presets shipped in assets/ and the scenes beside the one running.
std::vector<std::string> presetPaths(const std::string& sceneDir) {
    std::vector<std::string> out;
    const std::string assets = std::filesystem::path(COREBOX_DEFAULT_SCENE).parent_path().string();
    for (const std::string& dir : {assets, sceneDir}) {
        glob_t g{};
        if (glob((dir + "/*.toml").c_str(), 0, nullptr, &g) == 0) {
            for (size_t k = 0; k < g.gl_pathc; ++k) {
                const std::string path = std::filesystem::weakly_canonical(g.gl_pathv[k]).string();
                if (std::find(out.begin(), out.end(), path) == out.end()) out.push_back(path);
            }
        }
        globfree(&g);
    }
    return out;
}

Image readDefaultFramebuffer(int width, int height) {
    Image img{width, height, std::vector<uint8_t>(size_t(width) * size_t(height) * 4)};
    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    glReadBuffer(GL_BACK);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, img.rgba.data());
    flipRows(img.rgba, width, height);
    return img;
}

std::string timestampedScreenshotName() {
    char name[64];
    const std::time_t now = std::time(nullptr);
    std::strftime(name, sizeof name, "corebox-%Y%m%d-%H%M%S.png", std::localtime(&now));
    return name;
}

void reportInstability(const InstabilityError& e, LiveRun& live, const RunOptions& options) {
    std::fprintf(stderr, "corebox: %s\n", e.what());
    try {
        live.finish();
        const std::string path = lastGoodPath(options);
        writeStateCsv(path, live.simulation().lastGoodState());
        std::fprintf(stderr, "corebox: last good state written to %s\n", path.c_str());
    } catch (const std::exception& w) {
        std::fprintf(stderr, "corebox: error: %s\n", w.what());
    }
}

// Runs a frame loop and turns its errors into exit codes (DESIGN.md sec. 3); after a blow-up the
// observables so far are kept and the last good state is written.
template <class Body>
int guardedRun(const RunOptions& options, std::unique_ptr<LiveRun>& live, Body&& body) {
    try {
        body();
    } catch (const InstabilityError& e) {
        if (live) reportInstability(e, *live, options);
        else std::fprintf(stderr, "corebox: %s\n", e.what());
        return kExitUnstable;
    } catch (const InputError& e) {
        std::fprintf(stderr, "corebox: error: %s\n", e.what());
        return kExitInput;
    } catch (const PlatformError& e) {
        std::fprintf(stderr, "corebox: device error: %s\n", e.what());
        return kExitDevice;
    } catch (const RenderError& e) {
        std::fprintf(stderr, "corebox: device error: %s\n", e.what());
        return kExitDevice;
    } catch (const DeviceError& e) {
        std::fprintf(stderr, "corebox: device error: %s\n", e.what());
        return kExitDevice;
    } catch (const std::runtime_error& e) {  // frame, screenshot or video output
        std::fprintf(stderr, "corebox: error: %s\n", e.what());
        return kExitInput;
    }
    return kExitOk;
}

RenderStyle styleOf(LiveRun& live) {
    return renderStyleFor(live.simulation().scene(), live.display().colorBySpeed ? ColorMode::Speed : ColorMode::Species);
}

// Keeps the instance feed matched to the session's current backend.
struct Feed {
    std::unique_ptr<InstanceFeed> feed;
    uint64_t generation = ~uint64_t(0);
    bool colorBySpeed = false;
    void update(LiveRun& live, ParticleRenderer& renderer) {
        if (!feed || generation != live.session().generation() || colorBySpeed != live.display().colorBySpeed) {
            colorBySpeed = live.display().colorBySpeed;
            feed = std::make_unique<InstanceFeed>(live.simulation(), renderer, colorBySpeed ? ColorMode::Speed : ColorMode::Species);
            generation = live.session().generation();
        }
        feed->update();
    }
};

}  // namespace

int runHeadlessFrames(const RunOptions& options, const Scene& scene) {
    const HeadlessOptions& h = options.headless;
    std::unique_ptr<LiveRun> livePtr;
    return guardedRun(options, livePtr, [&] {
        livePtr = std::make_unique<LiveRun>(scene, BackendChoice{options.backend.name, scene.integrator.precision, options.backend.threads, 0},
                                            liveOptions(options, h.stepsPerFrame));
        LiveRun& live = *livePtr;
        live.display().colorBySpeed = h.colorBy == "speed";
        live.display().stepsPerFrame = int(h.stepsPerFrame);
        int width = 0, height = 0;
        std::sscanf(h.size.c_str(), "%dx%d", &width, &height);
        FrameDumpOptions dump;
        dump.outDir = h.outDir;
        dump.width = width;
        dump.height = height;
        dump.videoPath = h.videoPath;
        dump.context.softwareOnly = h.softwareOnly;
        dump.context.cudaDevice = h.softwareOnly ? -1 : interopDeviceFor(live.simulation().backend());
        const std::array<float, 3> box{float(scene.box.size[0]), float(scene.box.size[1]), float(scene.box.size[2])};
        std::unique_ptr<FrameDumper> frames;
        try {
            frames = std::make_unique<FrameDumper>(dump, box);
        } catch (const PlatformError& e) {
            if (dump.context.cudaDevice < 0) throw;
            std::fprintf(stderr, "[corebox] warning: %s; rendering on another EGL device without interop\n", e.what());
            dump.context.cudaDevice = -1;
            frames = std::make_unique<FrameDumper>(dump, box);
        }
        std::unique_ptr<ImGuiLayer> hud;
        if (h.hud) hud = std::make_unique<ImGuiLayer>(nullptr, "");
        Feed feed;
        std::fprintf(stderr, "[corebox] headless rendering on %s\n", frames->contextDescription().c_str());
        ProgressReporter progress((h.frames - 1) * h.stepsPerFrame, !options.quiet);
        auto overlay = [&](int w, int hgt) {
            live.refreshSpeedDistributions();
            hud->beginFrame(w, hgt, 1.0 / 30.0);
            drawHud(live.speeds(), live.history(), live.performance(), float(w), float(hgt));
            hud->endFrame();
        };
        auto render = [&](int64_t index) {
            Clock::time_point t = Clock::now();
            feed.update(live, frames->renderer());
            const double msFeed = msSince(t);
            t = Clock::now();
            frames->writeFrame(index, styleOf(live), hud ? std::function<void(int, int)>(overlay) : std::function<void(int, int)>());
            live.recordFrame(msFeed, msSince(t));
        };
        render(0);
        for (int64_t f = 1; f < h.frames; ++f) {
            const ScriptEffects e = live.advance(live.display().paused ? 0 : live.display().stepsPerFrame);
            if (e.reset) live.reset();
            render(f);
            if (!e.screenshotPath.empty()) {
                writePng(e.screenshotPath, frames->lastImage());
                std::fprintf(stderr, "[corebox] screenshot written to %s\n", e.screenshotPath.c_str());
            }
            progress.update(live.simulation().stepIndex(), live.simulation().time(), live.history().temperature.empty() ? 0.0 : live.history().temperature.back());
            if (e.quit) break;
        }
        if (!options.screenshotPath.empty()) writePng(options.screenshotPath, frames->lastImage());
        live.finish();
        if (!options.stateOutPath.empty()) writeStateCsv(options.stateOutPath, live.simulation().state());
        reportFrames(options, *frames);
    });
}

namespace {

struct Input {
    double scroll = 0;
};
Input g_input;
void onScroll(GLFWwindow*, double, double dy) { g_input.scroll += dy; }

// Edge-triggered key presses.
struct Keys {
    bool previous[GLFW_KEY_LAST + 1] = {};
    bool pressed(GLFWwindow* w, int key) {
        const bool down = glfwGetKey(w, key) == GLFW_PRESS;
        const bool edge = down && !previous[key];
        previous[key] = down;
        return edge;
    }
};

}  // namespace

int runWindow(const RunOptions& options, const Scene& scene) {
    std::unique_ptr<LiveRun> live;
    return guardedRun(options, live, [&] {
        GlfwWindow window(1600, 900, "corebox");
        glfwSetScrollCallback(window.handle(), onScroll);  // before ImGui, which chains to it
        const UiSettingsFile settingsFile = UiSettingsFile::standard();
        ImGuiLayer ui(window.handle(), settingsFile.imguiIniPath());
        BackendChoice choice{options.backend.name, scene.integrator.precision, options.backend.threads, 0};
        live = std::make_unique<LiveRun>(scene, choice, liveOptions(options, 10));
        settingsFile.load(live->display());
        ParticleRenderer renderer;
        Feed feed;
        OrbitCamera camera;
        Keys keys;
        const std::vector<std::string> presets = presetPaths(std::filesystem::path(scene.sourcePath).parent_path().string());
        Clock::time_point lastSpeeds = Clock::now() - std::chrono::seconds(1);
        int64_t frame = 0;
        bool quit = false, framedOnce = false;
        bool vsync = true;
        double lastX = 0, lastY = 0;
        while (!window.shouldClose() && !quit) {
            glfwPollEvents();
            DisplaySettings& display = live->display();
            PanelActions actions;
            if (!ui.wantsKeyboard()) {
                if (keys.pressed(window.handle(), GLFW_KEY_SPACE)) display.paused = !display.paused;
                if (keys.pressed(window.handle(), GLFW_KEY_RIGHT)) actions.singleStep = true;
                if (keys.pressed(window.handle(), GLFW_KEY_R)) actions.reset = true;
                if (keys.pressed(window.handle(), GLFW_KEY_F12)) actions.screenshot = true;
                if (keys.pressed(window.handle(), GLFW_KEY_H)) display.showPanel = !display.showPanel;
                if (keys.pressed(window.handle(), GLFW_KEY_F1)) display.showHelp = !display.showHelp;
                if (keys.pressed(window.handle(), GLFW_KEY_ESCAPE)) quit = true;
            }
            int width = 0, height = 0;
            window.framebufferSize(&width, &height);
            if (width <= 0 || height <= 0) continue;  // minimised
            const Scene& running = live->simulation().scene();
            const std::array<float, 3> box{float(running.box.size[0]), float(running.box.size[1]), float(running.box.size[2])};
            if (!framedOnce) {
                camera.frameBox({box[0], box[1], box[2]}, float(width) / float(height));
                framedOnce = true;
            }
            double x = 0, y = 0;
            glfwGetCursorPos(window.handle(), &x, &y);
            if (!ui.wantsMouse()) {
                if (glfwGetMouseButton(window.handle(), GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS) {
                    camera.orbit(-0.005f * float(x - lastX), 0.005f * float(y - lastY));
                }
                if (glfwGetMouseButton(window.handle(), GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS) {
                    camera.pan(0.0015f * float(x - lastX), 0.0015f * float(y - lastY));
                }
                if (g_input.scroll != 0) camera.zoom(float(std::pow(0.9, g_input.scroll)));
            }
            g_input.scroll = 0;
            lastX = x;
            lastY = y;

            // Simulation: the frame's steps, and the script.
            // At most ~40 ms of stepping per frame: the panel stays responsive at any steps/frame
            // (a script's timing is by step number, so it is unaffected).
            ScriptEffects effects = live->advance(display.paused ? 0 : display.stepsPerFrame, 0.04);
            if (Clock::now() - lastSpeeds > std::chrono::milliseconds(250)) {
                live->refreshSpeedDistributions();
                lastSpeeds = Clock::now();
            }

            // Draw the particles, then the panels.
            Clock::time_point t = Clock::now();
            feed.update(*live, renderer);
            const double msFeed = msSince(t);
            t = Clock::now();
            glBindFramebuffer(GL_FRAMEBUFFER, 0);
            glEnable(GL_MULTISAMPLE);
            RenderStyle style = styleOf(*live);
            style.showLegend = !display.showPanel;  // the panel lists the species and their colours itself
            renderer.render(camera, box, style, width, height);
            const double msRender = msSince(t);
            ui.beginFrame(width, height, 0);
            if (display.showPanel) {
                drawControlPanel(live->controls(), display, actions, presets, live->status);
                drawSpeedHistogram(live->speeds());
                drawTimePlots(live->history());
                drawPerformance(live->performance());
            }
            drawHelp(&display.showHelp);
            ui.endFrame();
            live->recordFrame(msFeed, msRender);
            if (display.vsync != vsync) window.setVsync(vsync = display.vsync);

            // Panel and script actions.
            if (actions.singleStep) effects.quit = effects.quit || live->advance(1).quit;
            if (actions.reset || effects.reset) {
                const std::string error = live->reset();
                live->status = error.empty() ? "reset" : "reset refused: " + error;
            }
            if (!actions.loadPreset.empty()) {
                try {
                    const std::string error = live->controls().load(loadScene(actions.loadPreset));
                    live->status = error.empty() ? "loaded " + actions.loadPreset : error;
                    if (error.empty()) live->reset();
                    framedOnce = false;
                } catch (const InputError& e) {
                    live->status = e.what();
                }
            }
            if (!actions.saveScenePath.empty()) {
                try {
                    saveScene(live->controls().pending(), actions.saveScenePath);
                    live->status = "scene saved to " + actions.saveScenePath;
                } catch (const InputError& e) {
                    live->status = e.what();
                }
            }
            const bool lastFrame = (options.headless.frames > 0 && frame + 1 >= options.headless.frames) || effects.quit || quit;
            if (actions.screenshot || !effects.screenshotPath.empty() || (lastFrame && !options.screenshotPath.empty())) {
                const std::string path = !effects.screenshotPath.empty() ? effects.screenshotPath
                                         : actions.screenshot          ? timestampedScreenshotName()
                                                                       : options.screenshotPath;
                writePng(path, readDefaultFramebuffer(width, height));
                live->status = "screenshot: " + std::filesystem::absolute(path).string();
                std::fprintf(stderr, "[corebox] %s\n", live->status.c_str());
            }
            glfwSwapBuffers(window.handle());
            window.setTitle("corebox - " + running.sourcePath + " - " + live->simulation().backend().name() + " (" +
                            (feed.feed && feed.feed->usesInterop() ? "interop" : "copy") + ") - " +
                            std::to_string(int(live->performance().stepsPerSecond)) + " steps/s");
            ++frame;
            if (lastFrame) break;
        }
        settingsFile.save(live->display());
        live->finish();
        if (!options.stateOutPath.empty()) writeStateCsv(options.stateOutPath, live->simulation().state());
    });
}

}  // namespace corebox
