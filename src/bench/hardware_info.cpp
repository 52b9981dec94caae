#include "hardware_info.h"

#include "host_info.h"

#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <ctime>
#include <thread>

#if COREBOX_WITH_CUDA
#include "cuda_backend.h"
#endif

namespace corebox {
namespace {

// What `command` prints on stdout, or "" when it cannot be run or exits non-zero (nvidia-smi missing,
// or present without a driver). Its stderr is dropped: a missing tool is not an error here.
std::string commandOutput(const std::string& command) {
    FILE* pipe = ::popen((command + " 2>/dev/null").c_str(), "r");
    if (!pipe) return "";
    std::string out;
    char buffer[4096];
    size_t got = 0;
    while ((got = std::fread(buffer, 1, sizeof buffer, pipe)) > 0) out.append(buffer, got);
    const int status = ::pclose(pipe);
    if (status == -1 || !WIFEXITED(status) || WEXITSTATUS(status) != 0) return "";
    return out;
}

std::string firstLine(const std::string& text) {
    const std::string line = text.substr(0, text.find('\n'));
    const size_t end = line.find_last_not_of(" \r\t");
    return end == std::string::npos ? "" : line.substr(0, end + 1);
}

}  // namespace

HardwareInfo hostHardware() {
    HardwareInfo info;
    info.hardwareThreads = int(std::thread::hardware_concurrency());
    info.cpuModel = cpuModelName();
    char host[256] = {};
    if (::gethostname(host, sizeof host - 1) == 0) info.hostName = host;
    return info;
}

GpuHardware gpuHardware() {
    GpuHardware info;
#if COREBOX_WITH_CUDA
    info.count = cudaDeviceCount();
    for (int d = 0; d < info.count; ++d) info.devices.push_back(cudaDeviceDescription(d));
#endif
    info.driverVersion = firstLine(commandOutput("nvidia-smi --query-gpu=driver_version --format=csv,noheader"));
    info.topology = commandOutput("nvidia-smi topo -m");
    return info;
}

std::string utcTimestamp() {
    const std::time_t now = std::time(nullptr);
    char buffer[32];
    std::strftime(buffer, sizeof buffer, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&now));
    return buffer;
}

}  // namespace corebox
