#include "rendered_run.h"

#include <algorithm>

#include "error_report.h"
#include "scene_drawing.h"

namespace corebox {
namespace {

ColorMode colorModeOf(LiveRun& live) { return live.display().colorBySpeed ? ColorMode::Speed : ColorMode::Species; }

}  // namespace

LiveRunOptions liveRunOptions(const RunOptions& options, int64_t observeEvery) {
    LiveRunOptions live;
    live.observeEvery = std::max<int64_t>(1, observeEvery);
    live.observablesPath = options.observablesPath;
    if (!options.scriptPath.empty()) live.script = Script::load(options.scriptPath);
    return live;
}

int runRendered(const RunOptions& options, std::unique_ptr<LiveRun>& live, const std::function<void()>& body) {
    return runReportingErrors(body, [&] {
        if (live) keepAfterInstability(options, live->simulation(), [&] { live->finish(); });
    });
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
