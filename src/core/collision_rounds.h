// The a posteriori collision stage of a step (DESIGN.md sec. 2; the report's sec. 4), written once
// for every backend. The report resolves the earliest event first until none remain; here that runs
// in parallel rounds: in each round every particle finds its earliest event (a pair overlap or a
// wall penetration, rewound to its contact time), and every event that is the earliest of each
// particle it touches is resolved. Those events form a matching, so a backend resolves them
// concurrently. A round looks again only where something happened: active particles (with an event
// in the previous round) against every neighbour, the others against active neighbours alone.
// The number of rounds is capped; when the cap is hit, a last search over every particle says
// whether overlaps remain, and the step reports it.
#pragma once

#include "backend.h"
#include "step_report.h"

namespace corebox {

// Runs the rounds on the backend's current state; fills the collision fields of `report`.
void resolveCollisions(Backend& backend, int maxRounds, StepReport& report);

}  // namespace corebox
