#include "hardware_info.h"

#include "host_info.h"

#include <unistd.h>

#include <ctime>
#include <thread>

namespace corebox {

HardwareInfo hostHardware() {
    HardwareInfo info;
    info.hardwareThreads = int(std::thread::hardware_concurrency());
    info.cpuModel = cpuModelName();
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
