#include "host_info.h"

#include <fstream>

namespace corebox {

const std::string& cpuModelName() {
    static const std::string name = [] {
        std::ifstream cpuinfo("/proc/cpuinfo");
        std::string line;
        while (std::getline(cpuinfo, line)) {
            const size_t colon = line.find(':');
            if (line.rfind("model name", 0) == 0 && colon != std::string::npos) return line.substr(colon + 2);
        }
        return std::string("CPU");
    }();
    return name;
}

}  // namespace corebox
