#include "progress.h"

#include <cstdio>
#include <memory>

namespace corebox {

ProgressReporter::ProgressReporter(int64_t totalSteps, bool enabled, double intervalSeconds)
    : m_total(totalSteps), m_enabled(enabled), m_interval(intervalSeconds), m_start(Clock::now()), m_last(m_start) {}

void ProgressReporter::update(int64_t step, double time, double temperature) {
    if (!m_enabled) return;
    const Clock::time_point now = Clock::now();
    if (std::chrono::duration<double>(now - m_last).count() < m_interval) return;
    m_last = now;
    print(step, time, temperature, "progress");
}

void ProgressReporter::finish(int64_t step, double time, double temperature) {
    if (m_enabled) print(step, time, temperature, "done");
}

void ProgressReporter::print(int64_t step, double time, double temperature, const char* label) {
    const double elapsed = std::chrono::duration<double>(Clock::now() - m_start).count();
    const double rate = elapsed > 0 ? double(step) / elapsed : 0.0;
    const double eta = rate > 0 ? double(m_total - step) / rate : 0.0;
    std::fprintf(stderr, "[corebox] %s: step %lld/%lld (%.0f%%)  t = %.4g  T = %.4g  %.1f steps/s  elapsed %.1f s  ETA %.1f s\n",
                 label, (long long)step, (long long)m_total, m_total > 0 ? 100.0 * double(step) / double(m_total) : 100.0, time,
                 temperature, rate, elapsed, eta);
}

SetupProgress setupProgressLines(bool enabled, double intervalSeconds) {
    if (!enabled) return nullptr;
    using Clock = std::chrono::steady_clock;
    auto last = std::make_shared<Clock::time_point>(Clock::now());
    return [last, intervalSeconds](const char* stage, int64_t done, int64_t total) {
        const Clock::time_point now = Clock::now();
        if (std::chrono::duration<double>(now - *last).count() < intervalSeconds) return;
        *last = now;
        std::fprintf(stderr, "[corebox] set-up: %s %lld/%lld (%.0f%%)\n", stage, (long long)done, (long long)total,
                     total > 0 ? 100.0 * double(done) / double(total) : 100.0);
    };
}

}  // namespace corebox
