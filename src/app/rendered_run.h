// Runs that draw: the interactive window (GLFW + ImGui panel) and headless frame dumping (EGL), both
// driving a LiveRun so panels, scripts and observables behave the same. Return the exit code.
#pragma once

#include "run_command.h"
#include "scene.h"

namespace corebox {

int runWindow(const RunOptions& options, const Scene& scene);
int runHeadlessFrames(const RunOptions& options, const Scene& scene);

}  // namespace corebox
