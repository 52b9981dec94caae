#include "hardware_info.h"

#include <unistd.h>

#include <ctime>
#include <fstream>
#include <thread>

namespace corebox {

HardwareInfo hostHardware() {
    HardwareInfo info;
    info.hardwareThreads = int(std::thread::hardware_concurrency());
    std::ifstream cpuinfo("/proc/cpuinfo");
    std::string line;
    while (std::getline(cpuinfo, line)) {
        if (line.rfind("model name", 0) == 0) {
            const size_t colon = line.find(':');
            if (colon != std::string::npos) info.cpuModel = line.substr(colon + 2);
            break;
        }
    }
    char host[256] = {};
    if (::gethostname(host, sizeof host - 1) == 0) info.hostName = host;
    return info;
}

std::string utcTimestamp() {
    const std::time_t now = std::time(nullptr);
    char buffer[32];
    std::strftime(buffer, sizeof buffer, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&now));
    return buffer;
}

}  // namespace corebox
