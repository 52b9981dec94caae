// The CPU this process runs on, for logs, the panel and benchmark records.
#pragma once

#include <string>

namespace corebox {

// "Intel(R) Xeon(R) ..." from /proc/cpuinfo, or "CPU" where that is not readable. Read once.
const std::string& cpuModelName();

}  // namespace corebox
