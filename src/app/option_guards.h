// Guards on the command line that CLI11 alone does not give. Its integer conversion saturates: a
// step count of 10^20 became 2^63 - 1 and a run that never ends, a seed of 10^20 the largest seed.
// addIntegerRangeChecks rejects, for every integer option of a command and its subcommands, a value
// that does not fit its 64-bit type, with the option's name. capThreads warns about and caps a CPU
// thread count above the cores present: more threads than cores only makes the OpenMP teams wait
// for each other, and the results do not depend on the count (deterministic sums).
#pragma once

#include <string>

namespace CLI {
class App;
}

namespace corebox {

void addIntegerRangeChecks(CLI::App& command);

// The thread count to use for `requested` (0: all cores); prints a warning naming `option` when it
// caps. The cap is the number of hardware threads.
int capThreads(int requested, const std::string& option);

}  // namespace corebox
