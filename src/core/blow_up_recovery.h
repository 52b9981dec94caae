// Going on after a blow-up: the run goes back to its last good state, halves dt and carries on
// (the window always; batch and headless runs with --recover).
//
// Design note. A recovery point is a checkpoint (checkpoint.h) taken in memory right after an
// observation passed the blow-up checks, with the scene that was running then. On an
// InstabilityError the simulation is rebuilt from that point on a fresh backend, exactly as a
// --restart rebuilds it (the path the checkpoint tests prove bit-identical), and then given the
// step parameters and thermostat that were running when it failed, with dt halved (an adaptive run
// also divides its tolerance by 10, since its dt is only where the controller starts). Taking the
// point's state but the failing run's parameters matters: the failure usually follows an edit
// (a dt jump from a script or the panel), and going back to the point's old dt would undo the
// user's choice rather than make it work. An edit of the potential since the point is re-applied
// as work done on the system (Simulation::setStepParameters), so the conserved sum stays exact.
// A point is replaced only after the run has passed another observation, so the attempts at one
// point are counted: after `maxAttempts` halvings without getting past it, the failure stands
// (exit code 3 in a batch run). Points are taken at every observation (batch runs: deterministic,
// the same input recovers the same way) or at most every `minSeconds` of wall time (the window,
// where a point of a large GPU system costs a download).
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "checkpoint.h"
#include "errors.h"
#include "scene.h"
#include "simulation.h"

namespace corebox {

// "non_finite", "escape", "energy_growth", "runaway", "adaptive_failed", "rounds_capped" or
// "failed": the kind of an InstabilityError, from its message.
std::string instabilityKind(const std::string& message);

struct RecoveryPolicy {
    int maxAttempts = 8;      // halvings at one point before the failure stands
    double minSeconds = 0;    // wall time between points (0: a point at every observation)
};

// One recovery, as the panel and the log say it.
struct RecoveryEvent {
    int64_t failedStep = 0;
    double failedTime = 0;
    int64_t resumedStep = 0;  // the point's step
    double resumedTime = 0;
    Method method = Method::Rk4;
    Precision precision = Precision::Fp64;
    double dtBefore = 0, dtAfter = 0;
    double toleranceBefore = 0, toleranceAfter = 0;  // adaptive runs only
    int attempt = 0;          // 1 for the first recovery at this point
    std::string kind;         // instabilityKind
    std::string message;      // the InstabilityError's
    // "step 812 (energy_growth): back to step 800, rk4 dt 0.02 -> 0.01"
    std::string summary() const;
};

using BackendMaker = std::function<std::unique_ptr<Backend>(const Scene&)>;

class BlowUpRecovery {
public:
    explicit BlowUpRecovery(RecoveryPolicy policy = {});

    // Takes a point now (at the start, after a reset or a precision switch).
    void remember(const Simulation& sim);
    // Takes a point when the policy says one is due; call right after sim.observe() returned.
    // Returns whether it took one.
    bool rememberIfDue(const Simulation& sim);
    bool hasPoint() const { return m_point.has_value(); }
    int64_t pointStep() const { return m_point ? m_point->checkpoint.step : 0; }

    // Replaces `sim` (which threw `error`) with a simulation rebuilt at the point with dt halved,
    // on a backend from `makeBackend`. Throws InstabilityError (the original message, saying that
    // recovery gave up) when the attempts at this point are spent or there is no point.
    RecoveryEvent recover(std::unique_ptr<Simulation>& sim, const InstabilityError& error, const BackendMaker& makeBackend);

    int recoveries() const { return m_recoveries; }

private:
    struct Point {
        Scene scene;
        SimulationCheckpoint checkpoint;
    };
    RecoveryPolicy m_policy;
    std::optional<Point> m_point;
    std::chrono::steady_clock::time_point m_taken;
    int m_attempts = 0;
    int m_recoveries = 0;
};

}  // namespace corebox
