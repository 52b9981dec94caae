#include "interruption.h"

#include <unistd.h>

#include <atomic>
#include <csignal>

#include "atomic_file.h"

namespace corebox {
namespace {

std::atomic<int> g_signal{0};
static_assert(std::atomic<int>::is_always_lock_free, "read and written by a signal handler");

extern "C" void onInterrupt(int signal) {
    int expected = 0;
    if (g_signal.compare_exchange_strong(expected, signal)) return;  // first: stop after this step
    removeTemporaryFiles();
    ::_exit(128 + signal);
}

}  // namespace

void installInterruptHandlers() {
    struct sigaction action {};
    action.sa_handler = onInterrupt;
    sigemptyset(&action.sa_mask);
    action.sa_flags = SA_RESTART;  // blocking reads and writes carry on; the loops poll the flag
    sigaction(SIGINT, &action, nullptr);
    sigaction(SIGTERM, &action, nullptr);
}

void ignoreBrokenPipes() { std::signal(SIGPIPE, SIG_IGN); }

int interruptSignal() { return g_signal.load(); }

int interruptExitCode() { return 128 + interruptSignal(); }

const char* interruptName() { return interruptSignal() == SIGTERM ? "SIGTERM" : "SIGINT"; }

std::string interruptedStatePath(const RunOptions& options) {
    if (!options.stateOutPath.empty()) return options.stateOutPath;
    // Beside a file, not beside a device: /dev/null's directory is no place for a state.
    if (!options.observablesPath.empty() && inspectOutput(options.observablesPath).kind != OutputKind::Stream) {
        const size_t slash = options.observablesPath.find_last_of('/');
        return (slash == std::string::npos ? std::string() : options.observablesPath.substr(0, slash + 1)) + "interrupted_state.csv";
    }
    return "corebox_interrupted_state.csv";
}

}  // namespace corebox
