// Which pair-force model a scene runs (DESIGN.md sec. 2: a scene runs the cheapest model that serves
// it), decided once per parameter change by the core and stated wherever a run is described (the
// start-up line, the observables header, the run summary, the panel).
//
// The automatic rule, in order:
//   - every epsilon 0                      -> none: hard spheres, no force pass at all;
//   - no cutoff                            -> all pairs (the report's model);
//   - the cutoff spans most of the box     -> all pairs: the r_c + skin neighbourhood of a particle
//     (a cube of edge 2 (r_c + skin), clipped to the box) covers half the box or more, so lists would
//     keep most pairs and add their bookkeeping;
//   - fewer particles than the backend's measured crossover -> all pairs;
//   - otherwise                            -> neighbour lists (Verlet lists of r_c + skin).
// `forces = "all_pairs"` or `"neighbour_list"` overrides the rule. Neighbour lists asked for with a
// cutoff of 0 (a live edit) fall back to all pairs, with the reason said; a cutoff beyond half the
// box keeps the lists (they stay exact: the cell walk clamps at the walls) and says that all pairs
// would do as well.
//
// Several species with different sigma: the cutoff r_c is one length for every pair (pair_table.h),
// so the lists use it for all pairs: the largest cutoff is the only cutoff.
#pragma once

#include <cstdint>
#include <string>

#include "scene.h"

namespace corebox {

struct ForceChoice {
    ForceModel model = ForceModel::AllPairs;  // AllPairs, NeighbourList or None; never Auto
    std::string reason;                        // one line for people: why this model
    std::string summary() const;               // "neighbour_list (N = 32000 above the crossover ...)"
};

// N at and above which neighbour lists beat all pairs on a backend ("cpu", "cuda"), measured with
// `corebox bench md --sizes ...` (docs/md_benchmark.md).
int64_t neighbourListCrossover(const std::string& backendName);

// backendHasLists: Backend::supportsNeighbourLists(); without them every model is all pairs.
ForceChoice chooseForceModel(const StepParameters& parameters, int64_t particleCount, const std::string& backendName,
                             bool backendHasLists = true);

// Fraction of the box within reach of one particle's neighbour list: prod_a min(2 (r_c + skin), L_a) / L_a.
double listReachFraction(const std::array<double, 3>& box, double reach);

}  // namespace corebox
