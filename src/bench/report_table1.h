// The report's own Table 1 (Playne & Hawick 2012, CSTN-139, sec. 7), transcribed by hand from
// reference/cstn-139-playne-hawick-2012.txt so that `corebox bench table1` prints it beside its own
// measurements. This is the one table of numbers in corebox that was typed: it is the report's, not a
// measurement of ours.
//
// What the report says of these figures: milliseconds per time step of its molecular dynamics
// simulation with pair potentials and hard-sphere collisions, RK4, all-pairs forces with the tiling
// algorithm, on four NVIDIA Tesla C2070 in a Dell C410x PCIe extender chassis (CUDA 4.0, GPUDirect
// 2.0), "presented for one fixed density", "accurate to +/-0.005 millisecs per timestep". It does not
// state the density, temperature, time step, hard-core radius or precision; the columns are its
// "Direct Transfer", "Direct Transfer (Async)" and "Direct Access", i.e. DT-S, DT-A and DA on P = 4.
#pragma once

#include <cstdint>
#include <optional>

namespace corebox {

struct ReportTable1Row {
    int64_t n;
    double dtsMs;  // Direct Transfer (cudaMemcpyPeer)
    double dtaMs;  // Direct Transfer (Async) (cudaMemcpyPeerAsync)
    double daMs;   // Direct Access
};

inline constexpr int kReportTable1Gpus = 4;
inline constexpr const char* kReportTable1Hardware = "4 x NVIDIA Tesla C2070 (Dell C410x PCIe chassis)";

// Table 1, row by row, as printed. The text extraction runs each row's last time into the next row's N
// ("3.522048" is 3.52, then N = 2048); every time has two decimals, which splits them unambiguously.
// clang-format off
inline constexpr ReportTable1Row kReportTable1[] = {
    //  N       DT-S     DT-A     DA
    {1024,     3.46,    2.66,    3.52},
    {2048,     5.55,    4.76,    5.58},
    {4096,     9.81,    9.03,    9.80},
    {8192,    18.78,   18.12,   18.73},
    {16384,   53.38,   52.26,   53.18},
    {32768,  194.56,  193.50,  193.78},
    {65536,  729.27,  727.75,  727.01},
};
// clang-format on

inline std::optional<ReportTable1Row> reportTable1Row(int64_t n) {
    for (const ReportTable1Row& row : kReportTable1) {
        if (row.n == n) return row;
    }
    return std::nullopt;
}

}  // namespace corebox
