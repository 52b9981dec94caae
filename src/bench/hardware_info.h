// What a benchmark ran on, recorded next to every figure: CPU model and threads; for GPU runs the
// devices CUDA sees, the driver and how the GPUs are linked (filled in by gpuHardware()).
//
// Design note. The link topology comes from `nvidia-smi topo -m` (NVLink counts, PCIe switches and
// CPU affinity in one table), captured as text: CUDA itself only answers "can these two GPUs access
// each other", which the p2p benchmark records on its own. Where nvidia-smi is not installed the
// driver and topology are left empty rather than guessed. nvidia-smi lists every GPU of the host,
// whatever CUDA_VISIBLE_DEVICES hides from this process; the device list below is what CUDA sees.
#pragma once

#include <string>
#include <vector>

namespace corebox {

struct HardwareInfo {
    std::string cpuModel;
    int hardwareThreads = 0;
    std::string hostName;
};

struct GpuHardware {
    int count = 0;                     // CUDA devices this process sees (0: no driver, no GPU or no CUDA build)
    std::vector<std::string> devices;  // cudaDeviceDescription of each: "NVIDIA H200 (CUDA driver 13.0, runtime 13.0)"
    std::string driverVersion;         // nvidia-smi's driver version ("580.95.05"); "" without nvidia-smi
    std::string topology;              // the output of `nvidia-smi topo -m`; "" without nvidia-smi
};

HardwareInfo hostHardware();
GpuHardware gpuHardware();
// ISO-8601 UTC time of now, for result files.
std::string utcTimestamp();

}  // namespace corebox
