#include "gpu_records.h"

#include <algorithm>
#include <cstdio>

#include <cstdio>
#include <sstream>

#include "atomic_file.h"

namespace corebox {

double median(std::vector<double> values) {
    std::sort(values.begin(), values.end());
    const size_t n = values.size();
    return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

std::string number(double value) {
    char text[40];
    std::snprintf(text, sizeof text, "%.6g", value);
    return text;
}

std::string csvQuote(const std::string& text) {
    std::string out = "\"";
    for (char c : text) out += c == '"' ? std::string("\"\"") : std::string(1, c);
    return out + "\"";
}

std::string csvComment(const std::string& text) {
    std::istringstream in(text);
    std::string out, line;
    while (std::getline(in, line)) out += line.empty() ? "#\n" : "# " + line + "\n";
    return out;
}

std::string gpuCsvPreamble(const std::string& command, const GpuHardware& gpus, const std::string& notes) {
    std::string out = csvComment(command) + csvComment(notes);
    out += "# gpus visible to CUDA: " + std::to_string(gpus.count) + "\n";
    for (size_t d = 0; d < gpus.devices.size(); ++d)
        out += "#   GPU " + std::to_string(d) + ": " + gpus.devices[d] + "\n";
    out += "# driver: " + (gpus.driverVersion.empty() ? std::string("unknown (no nvidia-smi)") : gpus.driverVersion) +
           "\n";
    if (gpus.topology.empty()) {
        out += "# topology: unknown (no nvidia-smi)\n";
    } else {
        out += "# topology (nvidia-smi topo -m):\n" + csvComment(gpus.topology);
    }
    return out;
}

nlohmann::json gpuHardwareJson(const GpuHardware& gpus) {
    return {{"count", gpus.count},
            {"devices", gpus.devices},
            {"driver", gpus.driverVersion},
            {"topology", gpus.topology},
            {"topology_source", gpus.topology.empty() ? "none (nvidia-smi not found)" : "nvidia-smi topo -m"}};
}

nlohmann::json hostJson(const HardwareInfo& host) {
    return {{"cpu", host.cpuModel}, {"hardware_threads", host.hardwareThreads}, {"name", host.hostName}};
}

void writeResultFiles(const std::string& prefix, const std::string& csv, const nlohmann::json& json) {
    AtomicFile csvFile(prefix + ".csv");
    AtomicFile jsonFile(prefix + ".json");
    csvFile.stream() << csv;
    jsonFile.stream() << json.dump(2) << "\n";
    csvFile.commit();
    jsonFile.commit();
    std::fprintf(stderr, "[corebox] wrote %s.csv and %s.json\n", prefix.c_str(), prefix.c_str());
}

}  // namespace corebox
