// Fills the panels' read-only views from the running simulation: speed distributions (histogram,
// KS statistic and temperatures, computed by the backend, on the GPU for CUDA) per species and
// for all particles.
#pragma once

#include "observables.h"
#include "simulation.h"
#include "ui_views.h"

namespace corebox {

void fillSpeedView(Simulation& sim, const ObservablesRow& row, SpeedView& view, int bins = 48);

}  // namespace corebox
