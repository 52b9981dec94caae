#include "force_model.h"

#include <algorithm>
#include <sstream>

namespace corebox {

namespace {

// At or above this reach fraction lists keep most pairs (the cube overestimates the sphere by 6/pi,
// so 0.5 of the box in the cube is about a quarter in the sphere, where the list bookkeeping and the
// rebuilds already cost what the skipped pairs save).
constexpr double kAllPairsReach = 0.5;

std::string formatted(double v) {
    std::ostringstream out;
    out << v;
    return out.str();
}

}  // namespace

std::string ForceChoice::summary() const { return std::string(forceModelName(model)) + " (" + reason + ")"; }

// CPU: measured with `corebox bench md --sizes 32,64,125,250,500 --precision fp64` on 2 cores
// (docs/results/md_cpu_crossover.json): all pairs is faster at N = 32, the half lists from N = 64 on.
// CUDA: measured with `corebox bench md --backend cuda --sizes 250,500,1000,2000,4000,8000` on an H200
// (docs/results/md_h200_crossover.json): lists are faster at every size, 0.029 against 0.259 ms per
// step at N = 250 in fp32 (their steps run ahead, their stage is screened; all pairs' stage is not),
// so the smallest size measured. (Before lists stepped ahead of the host, in 2026-11-22's record,
// all pairs was faster up to N = 8000.) Below it the box rule mostly decides: at this density the
// reach spans most of a box of fewer than ~150 particles.
int64_t neighbourListCrossover(const std::string& backendName) {
    if (backendName == "cuda") return 250;
    return 64;
}

double listReachFraction(const std::array<double, 3>& box, double reach) {
    double fraction = 1.0;
    for (double l : box) fraction *= l > 0 ? std::min(2.0 * reach, l) / l : 1.0;
    return fraction;
}

ForceChoice chooseForceModel(const StepParameters& parameters, int64_t particleCount, const std::string& backendName, bool backendHasLists) {
    const InteractionDef& in = parameters.interaction;
    const bool anyEpsilon = std::any_of(parameters.species.begin(), parameters.species.end(), [](const SpeciesDef& s) { return s.epsilon != 0.0; });
    if (!anyEpsilon) return {ForceModel::None, "every epsilon is 0: no pair force, hard cores only"};
    const double reach = in.cutoff + in.skin;
    const double minEdge = std::min({parameters.box.size[0], parameters.box.size[1], parameters.box.size[2]});
    if (in.forces == ForceModel::AllPairs) return {ForceModel::AllPairs, "asked for by the scene"};
    if (!backendHasLists && in.cutoff > 0) return {ForceModel::AllPairs, "the " + backendName + " backend has no neighbour lists yet"};
    if (in.forces == ForceModel::NeighbourList) {
        if (in.cutoff <= 0) return {ForceModel::AllPairs, "neighbour lists asked for, but there is no cutoff: every pair interacts"};
        if (in.cutoff > 0.5 * minEdge) {
            return {ForceModel::NeighbourList, "asked for by the scene; the cutoff " + formatted(in.cutoff) +
                                                   " exceeds half the smallest box edge, where all pairs would cost as little"};
        }
        return {ForceModel::NeighbourList, "asked for by the scene, r_c + skin = " + formatted(reach)};
    }
    if (in.cutoff <= 0) return {ForceModel::AllPairs, "no cutoff: every pair interacts"};
    const double fraction = listReachFraction(parameters.box.size, reach);
    if (fraction >= kAllPairsReach) {
        return {ForceModel::AllPairs, "the cutoff spans most of the box (r_c + skin reaches " + formatted(fraction * 100.0) + "% of it)"};
    }
    const int64_t crossover = neighbourListCrossover(backendName);
    if (particleCount < crossover) {
        return {ForceModel::AllPairs, "N = " + std::to_string(particleCount) + " is below the " + backendName + " crossover " +
                                          std::to_string(crossover) + " where lists start to pay"};
    }
    return {ForceModel::NeighbourList, "cutoff " + formatted(in.cutoff) + ", skin " + formatted(in.skin) + ", N = " + std::to_string(particleCount)};
}

}  // namespace corebox
