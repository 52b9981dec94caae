// The runs that draw: the interactive window (window_run.cpp: GLFW and the ImGui panel) and headless
// frame dumping (headless_run.cpp: EGL). Both drive a LiveRun, so panels, scripts and observables
// behave the same in either; this header also holds what the two frame loops share.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>

#include "instance_feed.h"
#include "live_run.h"
#include "particle_renderer.h"
#include "run_command.h"
#include "scene.h"

namespace corebox {

// Each returns the exit code (error_report.h).
int runWindow(const RunOptions& options, const Scene& scene);
int runHeadlessFrames(const RunOptions& options, const Scene& scene);

// The LiveRun settings of a rendered run: its observables file, its script, and an observables row
// every `observeEvery` steps.
LiveRunOptions liveRunOptions(const RunOptions& options, int64_t observeEvery);

// Runs a frame loop's `body` through the one error path (runReportingErrors); after a blow-up the
// observables so far and the last good state of `live` are kept, as in a batch run. An interrupted
// run that ended cleanly returns 128 + the signal.
int runRendered(const RunOptions& options, std::unique_ptr<LiveRun>& live, const std::function<void()>& body);

// The end of a frame loop: observables committed, the final state to --state-out; after SIGINT or
// SIGTERM (interruption.h) a last row for the current step, the state at interruptedStatePath and
// a line saying where both are.
void finishLiveRun(const RunOptions& options, LiveRun& live);

// The render style of the running scene in the colour mode the display settings ask for.
RenderStyle liveRenderStyle(LiveRun& live);

// The renderer's instance feed, kept matched to the session's backend (a restart or a precision
// switch replaces it) and to the colour mode (the panel and scripts switch it).
class LiveFeed {
public:
    void update(LiveRun& live, ParticleRenderer& renderer);
    bool usesInterop() const { return m_feed && m_feed->usesInterop(); }

private:
    std::unique_ptr<InstanceFeed> m_feed;
    uint64_t m_generation = ~uint64_t(0);
    ColorMode m_mode = ColorMode::Species;
};

}  // namespace corebox
