// What a benchmark ran on, recorded next to every figure: CPU model and threads (and, for GPU
// backends, the device name, driver and CUDA version filled in by the CUDA backend).
#pragma once

#include <string>

namespace corebox {

struct HardwareInfo {
    std::string cpuModel;
    int hardwareThreads = 0;
    std::string hostName;
};

HardwareInfo hostHardware();
// ISO-8601 UTC time of now, for result files.
std::string utcTimestamp();

}  // namespace corebox
