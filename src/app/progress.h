// Progress lines on stderr about every two seconds during long runs: step, percentage, rate, ETA
// and a physics vital sign (temperature), so a user sees a run is alive and where it is heading.
#pragma once

#include <chrono>
#include <cstdint>
#include <string>

#include "initial_conditions.h"

namespace corebox {

class ProgressReporter {
public:
    ProgressReporter(int64_t totalSteps, bool enabled, double intervalSeconds = 2.0);
    // Prints when the interval has passed since the last line.
    void update(int64_t step, double time, double temperature);
    void finish(int64_t step, double time, double temperature);

private:
    void print(int64_t step, double time, double temperature, const char* label);

    using Clock = std::chrono::steady_clock;
    int64_t m_total;
    bool m_enabled;
    double m_interval;
    Clock::time_point m_start;
    Clock::time_point m_last;
};

// Progress lines for the set-up of a scene (placement, overlap check), about every two seconds
// once it has lasted that long: small scenes print nothing. Null when not enabled.
SetupProgress setupProgressLines(bool enabled, double intervalSeconds = 2.0);

}  // namespace corebox
