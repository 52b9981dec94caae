// SIGINT and SIGTERM during a run (DESIGN.md sec. 3; issue 11).
//
// Design note. A run is interrupted between steps, never inside one: the first signal only sets a
// flag (an atomic, the one thing a handler may safely touch), the batch and headless loops poll it
// after each step, finish that step, write the observables so far and the current state, say where
// they are, and exit 128 + signal (130 for SIGINT, 143 for SIGTERM), the shell's convention for a
// process ended by a signal. A second signal means "now": the handler removes every temporary file
// still open (atomic_file.h keeps them in an async-signal-safe registry) and calls _exit at once.
// SIGPIPE is ignored for the whole process, so a closed pipe (stdout piped into `head`, an ffmpeg
// that refused its arguments) is a write error with a message, not a silent death.
#pragma once

#include <string>

#include "run_command.h"

namespace corebox {

// SIGPIPE ignored: every command's writes see EPIPE and report it. Call first thing in main.
void ignoreBrokenPipes();
// The handlers for SIGINT and SIGTERM, for the commands whose loops poll interruptRequested()
// (`corebox run`; the benchmarks keep the default: the first Ctrl-C ends them).
void installInterruptHandlers();

// The signal that asked the run to stop (SIGINT or SIGTERM), 0 when none has.
int interruptSignal();
inline bool interruptRequested() { return interruptSignal() != 0; }
// 128 + the signal: the exit code of an interrupted run.
int interruptExitCode();
// "SIGINT" or "SIGTERM".
const char* interruptName();

// Where an interrupted run writes its current state: --state-out when given, else
// interrupted_state.csv beside the observables, else corebox_interrupted_state.csv here.
std::string interruptedStatePath(const RunOptions& options);

}  // namespace corebox
