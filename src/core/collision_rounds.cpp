#include "collision_rounds.h"

namespace corebox {

void resolveCollisions(Backend& backend, int maxRounds, StepReport& report) {
    backend.beginCollisions();
    bool settled = false;
    for (int round = 0; round < maxRounds && !settled; ++round) {
        report.rounds = round + 1;
        settled = backend.findEvents(EventScope::Active) == 0;
        if (!settled) backend.applyEvents();
    }
    if (!settled) report.roundCapHit = backend.findEvents(EventScope::All) > 0;
    const CollisionTally tally = backend.collisionTally();
    report.pairCollisions = tally.pairCollisions;
    report.wallCollisions = tally.wallCollisions;
    report.positionalFixes = tally.positionalFixes;
    report.dissipated = tally.dissipated;
}

}  // namespace corebox
