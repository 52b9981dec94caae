// One error path for the command line: every front end (batch, headless and window runs, the
// benchmarks, main's own parse errors) turns an exception into an exit code and a message here
// (DESIGN.md sec. 3), so the same failure always reads and exits the same way.
//
//   InputError: a scene, file, flag or path; frame, video and screenshot output   2  corebox: error: ...
//   InstabilityError: the run blew up                                           3  corebox: ...
//   DeviceError (CUDA), PlatformError (EGL, GLFW), RenderError (GL), no memory    4  corebox: device error: ...
//   anything else is a bug in corebox                                            2  corebox: internal error: ...
//
// Device errors cover std::bad_alloc: buffers sized by the particle count are the allocations that
// fail, and the advice (fewer particles) is the same whether the memory was the GPU's or the host's.
#pragma once

#include <exception>
#include <functional>
#include <string>

namespace corebox {

enum ExitCode : int { kExitOk = 0, kExitInput = 2, kExitUnstable = 3, kExitDevice = 4 };

struct ErrorReport {
    ExitCode code = kExitInput;
    std::string message;  // the whole line for stderr, without the newline
};

ErrorReport describeError(const std::exception_ptr& error);

// Prints describeError(error).message on stderr and returns its code. Call it from a catch block,
// or with an exception made for the purpose (std::make_exception_ptr(InputError(...))).
int reportError(const std::exception_ptr& error = std::current_exception());

// Runs `body` and returns kExitOk, or reports what it threw and returns that code. After an
// instability `afterInstability` (when given) runs next, to keep what the run produced; its own
// failures are reported too but the exit code stays kExitUnstable.
int runReportingErrors(const std::function<void()>& body, const std::function<void()>& afterInstability = {});

}  // namespace corebox
