// What the multi-GPU benchmarks (`bench p2p`, `bench table1`) write beside their numbers, in one form:
// the command, the GPUs CUDA sees, the driver and the link topology, as comment lines at the top of the
// CSV (so the CSV alone says what made it) and as keys of the JSON.
//
// Design note. Comment lines start with "# " and come before the header row; the first is the
// command, as in every other benchmark's CSV, so readers skip lines starting with '#'. Files are
// written through AtomicFile: both appear whole, or neither.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "hardware_info.h"

namespace corebox {

std::string csvQuote(const std::string& text);
// A CSV field of `value` with 6 significant digits.
std::string number(double value);
// The median of the values (the mean of the middle two for an even count).
double median(std::vector<double> values);
// `text` with "# " before each of its lines (an empty line becomes "#").
std::string csvComment(const std::string& text);
// The comment lines: the command, then `notes` (what was measured, how it was timed), the GPUs and
// driver, and the topology table.
std::string gpuCsvPreamble(const std::string& command, const GpuHardware& gpus, const std::string& notes);
nlohmann::json gpuHardwareJson(const GpuHardware& gpus);
nlohmann::json hostJson(const HardwareInfo& host);
// Writes PREFIX.csv and PREFIX.json. Throws InputError naming the path when one cannot be written.
void writeResultFiles(const std::string& prefix, const std::string& csv, const nlohmann::json& json);

}  // namespace corebox
