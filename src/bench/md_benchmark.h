// `corebox bench md`: the cut-off LJ fluid of bench_scenes.h (mdScene) over N, steps per second and
// particle-steps per second, per backend, precision and force model (neighbour lists beside all
// pairs), and LAMMPS on the same starting state when it is installed (lammps_peer.h), so the ratio
// comes from one run on one machine. Writes PREFIX.csv (one row per measurement) and PREFIX.json.
//
// Design note. Each configuration is a fresh simulation: a few warm-up steps (the first list build,
// the first force pass), then steps until --min-seconds have passed (at least 3). A configuration whose
// predicted time (the previous size's step time of that model scaled by N for lists and N^2 for all
// pairs, times 3 steps) exceeds --max-seconds is skipped with a message rather than left running.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "scene.h"

namespace corebox {

struct MdBenchmarkOptions {
    std::string backend = "cpu";
    int threads = 0;  // CPU threads (0: all)
    std::vector<int64_t> sizes{4000, 32000, 64000, 1000000, 10000000};
    std::vector<Precision> precisions{Precision::Fp32, Precision::Fp64};
    std::vector<ForceModel> forces{ForceModel::NeighbourList, ForceModel::AllPairs};
    double minSeconds = 2.0;
    int64_t cpuMaxN = 200000;  // larger sizes run on the GPU only
    double maxSeconds = 60.0;  // skip a configuration predicted to need longer than this for 3 steps
    std::string lammps = "auto";  // "auto": run `lmp` when found (CPU backend); "off"; or the lmp binary
    int lammpsRanks = 2;
    std::string outputPrefix;
    std::string commandLine;
};

void runMdBenchmark(const MdBenchmarkOptions& options);

}  // namespace corebox
