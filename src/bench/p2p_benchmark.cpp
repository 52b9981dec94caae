#include "p2p_benchmark.h"

#include <algorithm>
#include <cstdio>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "atomic_file.h"
#include "errors.h"
#include "gpu_records.h"
#include "hardware_info.h"
#if COREBOX_WITH_CUDA
#include "peer_transfers.h"
#endif

namespace corebox {
namespace {

void checkOptions(const P2pBenchmarkOptions& o) {
    if (o.minBytes == 0 || (o.minBytes & (o.minBytes - 1)) != 0) {
        throw InputError("--min-bytes: must be a power of two, not " + std::to_string(o.minBytes));
    }
    if (o.maxBytes < o.minBytes) {
        throw InputError("--max-bytes: " + std::to_string(o.maxBytes) + " is below --min-bytes " +
                         std::to_string(o.minBytes));
    }
    if (o.repeats < 1) throw InputError("--repeats: must be >= 1");
    if (o.warmup < 0) throw InputError("--warmup: must be >= 0");
    if (o.gpus == 1 || o.gpus < 0) throw InputError("--gpus: at least 2 (0: every GPU)");
    for (Exchange m : o.methods) {
        if (m == Exchange::Auto)
            throw InputError("--methods: 'auto' is not a transfer method; name dts, dta, da or nccl");
    }
}

#if COREBOX_WITH_CUDA

const char* kTiming =
    "each repeat: every GPU j fetches GPU (j+1) mod P's buffer at the same time (NCCL: all-gather of every GPU's "
    "buffer); timed by the host clock (steady_clock) from cudaDeviceSynchronize on every GPU to "
    "cudaEventSynchronize of an event recorded after the transfer on every GPU's stream; median of the timed "
    "repeats after the warm-up ones";
const char* kMethods =
    "dts: cudaMemcpyPeer, blocking, issued GPU after GPU (the report's Listing 1); dta: cudaMemcpyPeerAsync on "
    "per-GPU streams, all queued at once (Listing 2); da: a kernel on the receiving GPU reads the peer's buffer "
    "over unified addressing (peer access enabled) and writes it to local memory (Listing 3); nccl: ncclAllGather "
    "in one ncclGroupStart/End, communicators from ncclCommInitAll";
const char* kPaths =
    "path: peer (direct GPU to GPU), host (no peer access: cudaMemcpyPeer stages the copy through host memory by "
    "itself), nccl (NCCL chooses its transport; NCCL_DEBUG=INFO names it), none (refused)";

constexpr const char* kCsvHeader =
    "method,gpus,bytes,bytes_received_per_gpu,repeats,median_s,min_s,max_s,gb_per_s_per_gpu,gb_per_s_total,path,"
    "verified,outcome,message,device\n";

// "4 KiB", "2 GiB": the sizes are powers of two.
std::string sizeName(uint64_t bytes) {
    const char* units[] = {"B", "KiB", "MiB", "GiB", "TiB"};
    int u = 0;
    double value = double(bytes);
    while (value >= 1024 && u < 4) {
        value /= 1024;
        ++u;
    }
    char text[32];
    std::snprintf(text, sizeof text, "%g %s", value, units[u]);
    return text;
}

std::vector<uint64_t> transferSizes(uint64_t minBytes, uint64_t maxBytes) {
    std::vector<uint64_t> sizes;
    for (uint64_t b = minBytes; b <= maxBytes; b *= 2) {
        sizes.push_back(b);
        if (b > maxBytes / 2) break;  // the next doubling would pass maxBytes (or wrap)
    }
    return sizes;
}

std::string csvRow(const P2pResult& r, const std::string& device) {
    const bool timed = r.outcome == "ok";
    return r.method + "," + std::to_string(r.gpus) + "," + std::to_string(r.bytes) + "," +
           std::to_string(r.bytesReceived) + "," + std::to_string(r.repeats) + "," +
           (timed ? number(r.medianSeconds) : "") + "," + (timed ? number(r.minSeconds) : "") + "," +
           (timed ? number(r.maxSeconds) : "") + "," + (timed ? number(r.gbPerSecondPerGpu) : "") + "," +
           (timed ? number(r.gbPerSecondTotal) : "") + "," + r.path + "," + (r.verified ? "yes" : "no") + "," +
           r.outcome + "," + csvQuote(r.message) + "," + csvQuote(device) + "\n";
}

nlohmann::json resultJson(const P2pResult& r) {
    const bool timed = r.outcome == "ok";
    auto orNull = [timed](double v) { return timed ? nlohmann::json(v) : nlohmann::json(nullptr); };
    return {{"method", r.method},
            {"gpus", r.gpus},
            {"bytes", r.bytes},
            {"bytes_received_per_gpu", r.bytesReceived},
            {"repeats", r.repeats},
            {"median_s", orNull(r.medianSeconds)},
            {"min_s", orNull(r.minSeconds)},
            {"max_s", orNull(r.maxSeconds)},
            {"gb_per_s_per_gpu", orNull(r.gbPerSecondPerGpu)},
            {"gb_per_s_total", orNull(r.gbPerSecondTotal)},
            {"path", r.path},
            {"verified", r.verified},
            {"outcome", r.outcome},
            {"message", r.message}};
}

// Every size of one method. A failure ends the method: its remaining sizes are rows with the message.
void measureMethod(PeerTransfers& transfers, const P2pBenchmarkOptions& o, Exchange method,
                   const std::vector<uint64_t>& sizes, std::vector<P2pResult>& out) {
    const int p = transfers.gpus();
    const std::string refusal = transfers.refusal(method);
    std::string failure, outcome;
    if (!refusal.empty()) {
        failure = refusal;
        outcome = "refused";
        std::fprintf(stderr, "[corebox] bench p2p: %s refused: %s\n", exchangeName(method), refusal.c_str());
    }
    for (uint64_t bytes : sizes) {
        P2pResult r;
        r.method = exchangeName(method);
        r.gpus = p;
        r.bytes = bytes;
        r.bytesReceived = method == Exchange::Nccl ? uint64_t(p - 1) * bytes : bytes;
        r.path = !refusal.empty()            ? "none"
                 : method == Exchange::Nccl  ? "nccl"
                 : transfers.viaHost(method) ? "host"
                                             : "peer";
        if (!failure.empty()) {
            r.outcome = outcome;
            r.message = failure;
            out.push_back(r);
            continue;
        }
        try {
            transfers.clearDestinations();
            for (int k = 0; k < o.warmup; ++k) transfers.timeOnce(method, bytes);
            std::vector<double> times;
            for (int k = 0; k < o.repeats; ++k) times.push_back(transfers.timeOnce(method, bytes));
            r.repeats = int(times.size());
            r.medianSeconds = median(times);
            r.minSeconds = *std::min_element(times.begin(), times.end());
            r.maxSeconds = *std::max_element(times.begin(), times.end());
            r.gbPerSecondPerGpu = double(r.bytesReceived) / r.medianSeconds / 1e9;
            r.gbPerSecondTotal = p * r.gbPerSecondPerGpu;
            r.verified = transfers.verify(method, bytes);
            r.outcome = "ok";
            if (!r.verified) r.message = "the received bytes are not the neighbour's pattern";
            std::fprintf(stderr, "[corebox] bench p2p: %-4s %2d GPUs %9s: %10.1f us, %7.2f GB/s per GPU%s%s\n",
                         r.method.c_str(), p, sizeName(bytes).c_str(), 1e6 * r.medianSeconds, r.gbPerSecondPerGpu,
                         r.path == "host" ? " (through host)" : "", r.verified ? "" : "  NOT VERIFIED");
        } catch (const DeviceError& e) {
            failure = e.what();
            outcome = "device_error";
        } catch (const std::exception& e) {
            failure = e.what();
            outcome = "error";
        }
        if (!failure.empty() && r.outcome.empty()) {
            std::fprintf(stderr, "[corebox] bench p2p: %s failed at %s: %s\n", r.method.c_str(),
                         sizeName(bytes).c_str(), failure.c_str());
            r.outcome = outcome;
            r.message = failure;
        }
        out.push_back(r);
    }
}

#endif

}  // namespace

std::vector<P2pResult> runP2pBenchmark(const P2pBenchmarkOptions& options) {
    checkOptions(options);
#if !COREBOX_WITH_CUDA
    throw DeviceError(
        "bench p2p needs at least 2 CUDA devices; this build of corebox has no CUDA backend (built without nvcc)");
#else
    const GpuHardware gpus = gpuHardware();
    if (gpus.count < 2) {
        throw DeviceError(
            "bench p2p needs at least 2 CUDA devices; found " +
            (gpus.count == 0 ? std::string("none (no NVIDIA driver or no GPU)") : "1: " + gpus.devices.front()));
    }
    const int p = options.gpus == 0 ? gpus.count : options.gpus;
    if (p > gpus.count) {
        throw DeviceError("--gpus " + std::to_string(p) + ": only " + std::to_string(gpus.count) +
                          " CUDA devices found");
    }
    if (!options.outputPrefix.empty()) {
        AtomicFile probe(options.outputPrefix + ".json");  // an unwritable --out fails now, not after the runs
    }
    const std::vector<uint64_t> sizes = transferSizes(options.minBytes, options.maxBytes);
    std::fprintf(stderr, "[corebox] bench p2p: %d GPUs, %s to %s, %d repeats after %d warm-up\n", p,
                 sizeName(sizes.front()).c_str(), sizeName(sizes.back()).c_str(), options.repeats, options.warmup);
    PeerTransfers transfers(p, sizes.back());
    std::vector<P2pResult> results;
    for (Exchange method : options.methods) measureMethod(transfers, options, method, sizes, results);

    const std::string device = gpus.devices.front();
    nlohmann::json access = nlohmann::json::array();
    for (int r = 0; r < p; ++r) {
        nlohmann::json row = nlohmann::json::array();
        for (int o = 0; o < p; ++o) row.push_back(r == o ? true : transfers.canAccessPeer(r, o));
        access.push_back(row);
    }
    std::string csv =
        gpuCsvPreamble(options.commandLine, gpus,
                       std::string("bench p2p on ") + std::to_string(p) + " GPUs; " + kTiming + "\n" + kMethods + "\n" +
                           kPaths + (transfers.ncclVersion().empty() ? "" : "\n" + transfers.ncclVersion()));
    std::string table = kCsvHeader;
    for (const P2pResult& r : results) table += csvRow(r, device);
    std::cout << table;
    if (options.outputPrefix.empty()) return results;
    nlohmann::json json;
    json["benchmark"] = "p2p";
    json["command"] = options.commandLine;
    json["timestamp"] = utcTimestamp();
    json["host"] = hostJson(hostHardware());
    json["gpu"] = gpuHardwareJson(gpus);
    json["device"] = device;
    json["gpus_used"] = p;
    json["peer_access"] = access;  // [reader][owner]: cudaDeviceCanAccessPeer
    json["nccl"] = transfers.ncclVersion();
    json["timing"] = kTiming;
    json["methods"] = kMethods;
    json["paths"] = kPaths;
    json["warmup"] = options.warmup;
    json["repeats"] = options.repeats;
    json["results"] = nlohmann::json::array();
    for (const P2pResult& r : results) json["results"].push_back(resultJson(r));
    writeResultFiles(options.outputPrefix, csv + table, json);
    return results;
#endif
}

}  // namespace corebox
