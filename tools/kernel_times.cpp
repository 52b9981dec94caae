// Kernel times of any CUDA program, without Nsight Systems (the device machines have none that makes a
// report): a CUPTI activity injection library. CUDA loads it into the program named by
// CUDA_INJECTION64_PATH and calls InitializeInjection; it records every kernel, copy and memset (and,
// with KERNEL_TIMES_API set, every runtime API call, whose time is the host's: its waits show as
// cudaStreamSynchronize and cudaEventSynchronize) and, as the program exits, writes one CSV row per
// window of GPU time and name: window,name,count,ns. A row named BUSY per window is the time the GPU ran
// anything of it (overlaps counted once), so a window's idle time is its length less BUSY.
//   KERNEL_TIMES_OUT        the CSV (default kernel_times.csv)
//   KERNEL_TIMES_WINDOW_MS  the window (default 250 ms); a pile's landing and its settled seconds apart
//   KERNEL_TIMES_API        also the runtime API calls, named "API:<call>"
//   KERNEL_TIMES_GAPS       also a CSV of the GPU's idle stretches, by the activities around them (writeGaps)
// scripts/kernel-times builds it and runs a command under it; scripts/summarise_kernel_times.py sums the
// windows and demangles the names. CUPTI costs a little a launch: time the program without it.
#include <cupti.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <mutex>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

namespace {

struct Activity {
    uint64_t start, end;  // ns, CUPTI's clock
    bool onHost;          // an API call: the host's time, not the GPU's
    std::string name;
};

std::mutex g_mutex;
std::vector<Activity> g_activities;

void CUPTIAPI bufferRequested(uint8_t** buffer, size_t* size, size_t* maxRecords) {
    *size = size_t(8) << 20;
    *buffer = static_cast<uint8_t*>(std::aligned_alloc(8, *size));
    *maxRecords = 0;
}

void CUPTIAPI bufferCompleted(CUcontext, uint32_t, uint8_t* buffer, size_t, size_t validSize) {
    CUpti_Activity* record = nullptr;
    std::lock_guard<std::mutex> lock(g_mutex);
    while (cuptiActivityGetNextRecord(buffer, validSize, &record) == CUPTI_SUCCESS) {
        switch (record->kind) {
            case CUPTI_ACTIVITY_KIND_CONCURRENT_KERNEL:
            case CUPTI_ACTIVITY_KIND_KERNEL: {
                const auto* k = reinterpret_cast<const CUpti_ActivityKernel10*>(record);
                g_activities.push_back({k->start, k->end, false, k->name ? k->name : "?"});
                break;
            }
            case CUPTI_ACTIVITY_KIND_MEMCPY: {
                const auto* m = reinterpret_cast<const CUpti_ActivityMemcpy6*>(record);
                g_activities.push_back({m->start, m->end, false, "memcpy kind " + std::to_string(int(m->copyKind))});
                break;
            }
            case CUPTI_ACTIVITY_KIND_MEMSET: {
                const auto* m = reinterpret_cast<const CUpti_ActivityMemset4*>(record);
                g_activities.push_back({m->start, m->end, false, "memset"});
                break;
            }
            case CUPTI_ACTIVITY_KIND_RUNTIME: {
                const auto* a = reinterpret_cast<const CUpti_ActivityAPI*>(record);
                const char* name = nullptr;
                cuptiGetCallbackName(CUPTI_CB_DOMAIN_RUNTIME_API, a->cbid, &name);
                g_activities.push_back({a->start, a->end, true, std::string("API:") + (name ? name : "?")});
                break;
            }
            default:
                break;
        }
    }
    std::free(buffer);
}

// KERNEL_TIMES_GAPS: where the GPU waits. Each stretch with nothing running on the GPU, per window, by the
// activity that ran last before it and the one that ends it (CSV window,before,after,count,ns); the
// waits for the host (its syncs, its launches) show as the pairs of kernels they sit between. With several
// GPUs a stretch is one where none of them ran anything.
void writeGaps(uint64_t t0, uint64_t windowNs) {
    const char* out = std::getenv("KERNEL_TIMES_GAPS");
    if (!out) return;
    std::map<std::tuple<uint64_t, std::string, std::string>, std::pair<uint64_t, uint64_t>> gaps;
    uint64_t coveredTo = 0;
    const std::string* last = nullptr;
    for (const Activity& a : g_activities) {
        if (a.onHost) continue;
        if (last && a.start > coveredTo) {
            auto& g = gaps[{(coveredTo - t0) / windowNs, *last, a.name}];
            g.first += 1;
            g.second += a.start - coveredTo;
        }
        if (a.end >= coveredTo) {
            coveredTo = a.end;
            last = &a.name;
        }
    }
    FILE* f = std::fopen(out, "w");
    if (!f) return;
    std::fprintf(f, "window,before,after,count,ns\n");
    for (const auto& [key, g] : gaps)
        std::fprintf(f, "%llu,\"%s\",\"%s\",%llu,%llu\n", (unsigned long long)std::get<0>(key),
                     std::get<1>(key).c_str(), std::get<2>(key).c_str(), (unsigned long long)g.first,
                     (unsigned long long)g.second);
    std::fclose(f);
}

void writeTimes() {
    cuptiActivityFlushAll(1);
    std::lock_guard<std::mutex> lock(g_mutex);
    if (g_activities.empty()) return;
    std::sort(g_activities.begin(), g_activities.end(),
              [](const Activity& a, const Activity& b) { return a.start < b.start; });
    const char* window = std::getenv("KERNEL_TIMES_WINDOW_MS");
    const uint64_t windowNs = uint64_t((window ? std::atof(window) : 250.0) * 1e6);
    if (windowNs == 0) return;
    const uint64_t t0 = g_activities.front().start;
    std::map<std::pair<uint64_t, std::string>, std::pair<uint64_t, uint64_t>> sums;  // count, ns
    std::map<uint64_t, uint64_t> busy;
    uint64_t coveredTo = 0;  // the GPU's work is counted once where launches overlap
    for (const Activity& a : g_activities) {
        const uint64_t w = (a.start - t0) / windowNs;
        auto& s = sums[{w, a.name}];
        s.first += 1;
        s.second += a.end - a.start;
        if (a.onHost) continue;
        const uint64_t from = std::max(a.start, coveredTo);
        if (a.end > from) busy[w] += a.end - from;
        coveredTo = std::max(coveredTo, a.end);
    }
    writeGaps(t0, windowNs);
    const char* out = std::getenv("KERNEL_TIMES_OUT");
    FILE* f = std::fopen(out ? out : "kernel_times.csv", "w");
    if (!f) {
        std::fprintf(stderr, "kernel_times: cannot write %s\n", out ? out : "kernel_times.csv");
        return;
    }
    std::fprintf(f, "window,name,count,ns\n");
    for (const auto& [key, s] : sums)
        std::fprintf(f, "%llu,\"%s\",%llu,%llu\n", (unsigned long long)key.first, key.second.c_str(),
                     (unsigned long long)s.first, (unsigned long long)s.second);
    for (const auto& [w, ns] : busy)
        std::fprintf(f, "%llu,\"BUSY\",0,%llu\n", (unsigned long long)w, (unsigned long long)ns);
    std::fclose(f);
}

}  // namespace

extern "C" int InitializeInjection(void) {
    if (cuptiActivityRegisterCallbacks(bufferRequested, bufferCompleted) != CUPTI_SUCCESS) {
        std::fprintf(stderr, "kernel_times: CUPTI refused the activity callbacks; no times\n");
        return 1;
    }
    cuptiActivityEnable(CUPTI_ACTIVITY_KIND_CONCURRENT_KERNEL);
    cuptiActivityEnable(CUPTI_ACTIVITY_KIND_MEMCPY);
    cuptiActivityEnable(CUPTI_ACTIVITY_KIND_MEMSET);
    if (std::getenv("KERNEL_TIMES_API")) cuptiActivityEnable(CUPTI_ACTIVITY_KIND_RUNTIME);
    std::atexit(writeTimes);
    return 1;
}
