// A run without rendering (`corebox run SCENE` with no display, or --no-window): observables to a
// file or stdout, the final state, progress lines on stderr.
#pragma once

#include "run_command.h"
#include "scene.h"

namespace corebox {

// Returns the exit code (error_report.h).
int runBatch(const RunOptions& options, const Scene& scene);

}  // namespace corebox
