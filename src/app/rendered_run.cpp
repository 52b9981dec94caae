#include "rendered_run.h"

#include "progress.h"

#include <algorithm>
#include <cstdio>

#include "error_report.h"
#include "interruption.h"
#include "state_csv.h"
#include "scene_drawing.h"

namespace corebox {
namespace {

ColorMode colorModeOf(LiveRun& live) { return live.display().colorBySpeed ? ColorMode::Speed : ColorMode::Species; }

}  // namespace

LiveRunOptions liveRunOptions(const RunOptions& options, int64_t observeEvery) {
    LiveRunOptions live;
    live.observeEvery = std::max<int64_t>(1, observeEvery);
    live.observablesPath = options.observablesPath;
    live.quiet = options.quiet;
    if (!options.scriptPath.empty()) live.script = Script::load(options.scriptPath);
    live.setupProgress = setupProgressLines(!options.quiet);
    live.recover = options.recover;
    live.integratorChoice = options.integratorChoice;
    live.studyPath = options.studyPath;
    return live;
}

int runRendered(const RunOptions& options, std::unique_ptr<LiveRun>& live, const std::function<void()>& body) {
    const int code = runReportingErrors(body, [&] {
        if (live) keepAfterInstability(options, live->simulation(), [&] { live->finish(); });
    });
    return code == kExitOk && interruptRequested() ? interruptExitCode() : code;
}

void finishLiveRun(const RunOptions& options, LiveRun& live) {
    if (!interruptRequested()) {
        live.finish();
        if (!options.stateOutPath.empty()) writeStateCsv(options.stateOutPath, live.simulation().state());
        return;
    }
    live.observeNow();
    live.finish();
    const std::string statePath = interruptedStatePath(options);
    writeStateCsv(statePath, live.simulation().state());
    std::fprintf(stderr, "[corebox] %s: stopped after step %lld; observables in %s, state in %s\n", interruptName(),
                 (long long)live.simulation().stepIndex(), options.observablesPath.empty() ? "(none)" : options.observablesPath.c_str(),
                 statePath.c_str());
}

RenderStyle liveRenderStyle(LiveRun& live) { return renderStyleFor(live.simulation().scene(), colorModeOf(live)); }

void LiveFeed::update(LiveRun& live, ParticleRenderer& renderer) {
    if (!m_feed || m_generation != live.session().generation() || m_mode != colorModeOf(live)) {
        m_mode = colorModeOf(live);
        m_feed = std::make_unique<InstanceFeed>(live.simulation(), renderer, m_mode);
        m_generation = live.session().generation();
    }
    m_feed->update();
}

}  // namespace corebox
