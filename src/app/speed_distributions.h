// Measures what the speed histogram panel shows, from the running simulation: speed distributions
// (histogram, KS statistic and temperatures, computed by the backend, on the GPU for CUDA) per
// species and for all particles.
#pragma once

#include "observables.h"
#include "simulation.h"
#include "panel_data.h"

namespace corebox {

void measureSpeedDistributions(Simulation& sim, const ObservablesRow& row, SpeedDistributionData& speeds, int bins = 48);

}  // namespace corebox
