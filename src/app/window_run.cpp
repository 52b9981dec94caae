// The window frame loop (`corebox` or `corebox run SCENE` where there is a display): GLFW window,
// particles drawn from simulation memory, the ImGui panels, keys and mouse, screenshots, presets.
#include <epoxy/gl.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <chrono>
#include <cstdio>
#include <ctime>
#include <filesystem>

#include "errors.h"
#include "frame_dumper.h"
#include "glfw_window.h"
#include "imgui_layer.h"
#include "interruption.h"
#include "panels.h"
#include "preset_paths.h"
#include "rendered_run.h"
#include "scene_io.h"
#include "state_csv.h"
#include "ui_settings_file.h"
#include "window_input.h"

namespace corebox {
namespace {

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t) { return 1e3 * std::chrono::duration<double>(Clock::now() - t).count(); }

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

}  // namespace

int runWindow(const RunOptions& options, const Scene& scene) {
    std::unique_ptr<LiveRun> live;
    return runRendered(options, live, [&] {
        GlfwWindow window(1600, 900, "corebox");
        WindowInput input(window.handle());  // before ImGui, which chains to its scroll callback
        const UiSettingsFile settingsFile = UiSettingsFile::standard();
        ImGuiLayer ui(window.handle(), settingsFile.imguiIniPath());
        BackendChoice choice{options.backend.name, scene.integrator.precision, options.backend.threads, 0};
        // The window never ends on a blow-up: it goes back to a good state at most half a second old.
        LiveRunOptions liveOptions = liveRunOptions(options, 10);
        liveOptions.recover = true;
        liveOptions.recoveryPointSeconds = 0.5;
        live = std::make_unique<LiveRun>(scene, choice, liveOptions);
        settingsFile.load(live->display());
        ParticleRenderer renderer;
        LiveFeed feed;
        OrbitCamera camera;
        const std::vector<std::string> presets = presetPaths(std::filesystem::path(scene.sourcePath).parent_path().string());
        Clock::time_point lastSpeeds = Clock::now() - std::chrono::seconds(1);
        int64_t frame = 0;
        bool quit = false, framedOnce = false;
        bool vsync = true;
        while (!window.shouldClose() && !quit) {
            glfwPollEvents();
            DisplaySettings& display = live->display();
            PanelActions actions;
            input.readKeys(ui.wantsKeyboard(), display, actions, &quit);
            int width = 0, height = 0;
            window.framebufferSize(&width, &height);
            if (width <= 0 || height <= 0) continue;  // minimised
            const Scene& running = live->simulation().scene();  // before advance(): a reset or recovery replaces it
            const std::array<float, 3> box{float(running.box.size[0]), float(running.box.size[1]), float(running.box.size[2])};
            if (!framedOnce) {
                camera.frameBox({box[0], box[1], box[2]}, float(width) / float(height));
                framedOnce = true;
            }
            input.moveCamera(camera, ui.wantsMouse());

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
            RenderStyle style = liveRenderStyle(*live);
            style.showLegend = !display.showPanel;  // the panel lists the species and their colours itself
            renderer.render(camera, box, style, width, height);
            const double msRender = msSince(t);
            ui.beginFrame(width, height, 0);
            if (display.showPanel) {
                drawControlPanel(live->controls(), display, actions, presets, live->status);
                drawSpeedHistogram(live->speeds());
                drawTimePlots(live->history());
                drawPerformance(live->performance());
                drawSpeedAccuracy(live->speedAccuracy());
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
            const bool lastFrame =
                (options.headless.frames > 0 && frame + 1 >= options.headless.frames) || effects.quit || quit || interruptRequested();
            if (actions.screenshot || !effects.screenshotPath.empty() || (lastFrame && !options.screenshotPath.empty())) {
                const std::string path = !effects.screenshotPath.empty() ? effects.screenshotPath
                                         : actions.screenshot          ? timestampedScreenshotName()
                                                                       : options.screenshotPath;
                writeOutputPng(path, readDefaultFramebuffer(width, height));
                live->status = "screenshot: " + std::filesystem::absolute(path).string();
                std::fprintf(stderr, "[corebox] %s\n", live->status.c_str());
            }
            glfwSwapBuffers(window.handle());
            window.setTitle("corebox - " + live->simulation().scene().sourcePath + " - " + live->simulation().backend().name() + " (" +
                            (feed.usesInterop() ? "interop" : "copy") + ") - " +
                            std::to_string(int(live->performance().stepsPerSecond)) + " steps/s");
            ++frame;
            if (lastFrame) break;
        }
        settingsFile.save(live->display());
        finishLiveRun(options, *live);
    });
}

}  // namespace corebox
