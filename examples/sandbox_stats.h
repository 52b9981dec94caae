// Frame-time bookkeeping of the sandbox: per-frame samples, their summary (mean, median, p95, max),
// a once-a-second window for the HUD and stderr, and the --stats JSON file.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace sandbox {

struct FrameSample {
    double simMs = 0;     // world.advance() and the read of the state it leaves (pipelined: the step that
                          // ran on the worker while the frame before was drawn)
    double renderMs = 0;  // instances built and uploaded, the frame drawn and finished (glFinish)
    double waitMs = 0;    // pipelined: how long the frame waited for that step to end
    double frameMs = 0;   // the whole frame: input, simulation, drawing, buffer swap
    // Of simMs, the collision stage (corebox::StepInfo): impact rounds, the contact phase, and of it
    // the contact lists.
    double impactsMs = 0, contactsMs = 0, listingsMs = 0;
    // The contact lists the step made, and the deepest overlap its contact phase left [contact distances].
    double listings = 0, overlapLeft = 0;
};

struct Summary {
    double mean = 0, median = 0, p95 = 0, max = 0;
    size_t count = 0;
};

// p95 and the median by nearest rank on the sorted samples.
Summary summarise(std::vector<double> values);

// One field of the samples from `first` on (the summaries leave the first frames out).
std::vector<double> column(const std::vector<FrameSample>& samples, size_t first, double FrameSample::*field);

// Averages over the frames since the last reset (the HUD's and stderr's once-a-second figures).
struct Window {
    double simMs = 0, impactsMs = 0, contactsMs = 0, renderMs = 0, frameMs = 0, simMaxMs = 0;
    int frames = 0;
    void add(const FrameSample& s);
    // Frames over the wall time they spanned: paced frames (--pace) wait for their refresh outside frameMs.
    double fps(double elapsedMs) const { return elapsedMs > 0 ? 1e3 * frames / elapsedMs : 0.0; }
    double mean(double total) const { return frames > 0 ? total / frames : 0.0; }
};

// "AMD EPYC 7763 64-Core Processor" from /proc/cpuinfo, or "unknown".
std::string hostCpuName();

// A minimal JSON object writer (the example keeps its dependencies to corebox, the renderer and GLFW).
class JsonObject {
public:
    JsonObject& add(const std::string& key, const std::string& value);
    JsonObject& add(const std::string& key, const char* value) { return add(key, std::string(value)); }
    JsonObject& add(const std::string& key, double value);
    JsonObject& add(const std::string& key, int64_t value);
    JsonObject& add(const std::string& key, bool value);
    JsonObject& addNull(const std::string& key);
    JsonObject& add(const std::string& key, const Summary& s);
    JsonObject& add(const std::string& key, const std::vector<double>& values);  // an array, 3 decimals
    std::string text(bool multiline = false) const;  // multiline: a field a line (nested objects stay on one)

private:
    std::vector<std::pair<std::string, std::string>> m_fields;  // key, JSON value
};

std::string jsonString(const std::string& s);

}  // namespace sandbox
