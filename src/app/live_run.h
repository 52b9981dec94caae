// A run that is watched: the session, the panel's controls and display settings, the time series and
// speed distributions the panels show, performance figures, an optional script and an optional
// observables file. The window and the headless frame loop both drive one of these, so a script or
// a panel edit behaves the same in either.
//
// With recovery on (the window always, headless runs with --recover) a blow-up does not end the run:
// the session goes back to its last good state with dt halved (blow_up_recovery.h), the plots and the
// held observables rows after that state are dropped, and `status` says what failed and what changed.
//
// The speed-vs-accuracy panel's points: each integrator setting the run goes through (method,
// precision, dt; a live switch, a reset or a recovery starts a new one) gets the force passes per unit
// time and the least-squares drift rate of the conserved sum it showed, over the study's lines of
// this scene (study_curves.h).
#pragma once

#include <chrono>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "observables_output.h"
#include "script.h"
#include "script_runner.h"
#include "session.h"
#include "live_controls.h"
#include "panel_data.h"

namespace corebox {

struct LiveRunOptions {
    int64_t observeEvery = 10;     // observables row (and plot point) every K steps
    std::string observablesPath;   // "" : none
    std::optional<Script> script;
    SetupProgress setupProgress;   // long set-ups and restarts report here (progress.h); null: silent
    bool quiet = false;            // script lines only when refused, no force-model lines (--quiet)
    bool recover = false;          // go on after a blow-up (blow_up_recovery.h)
    std::string integratorChoice;  // method = "auto": the pilot's choice, for the panel
    std::string studyPath;         // the speed-vs-accuracy panel's lines ("": looked for beside the scene)
    double recoveryPointSeconds = 0;  // wall time between recovery points (0: at every observation)
};

class LiveRun {
public:
    // Throws InputError / DeviceError.
    LiveRun(const Scene& scene, const BackendChoice& backend, LiveRunOptions options, SimulationLimits limits = {});

    Session& session() { return m_session; }
    Simulation& simulation() { return m_session.simulation(); }
    LiveControls& controls() { return m_controls; }
    DisplaySettings& display() { return m_display; }

    // Runs up to `steps` steps (stopping early for a script's quit/screenshot/reset, or once
    // `budgetSeconds` > 0 of stepping has passed, so a window stays responsive whatever steps/frame
    // asks, or after the step in progress when SIGINT/SIGTERM arrives: interruption.h), observing
    // when due. Throws InstabilityError (with recovery on: only when recovery gives up).
    ScriptEffects advance(int64_t steps, double budgetSeconds = 0);
    // Restart from the controls' pending scene; clears the plots.
    std::string reset();
    // Speed distributions and performance for the panels (the O(N) speed statistics: call a few
    // times a second, not every frame).
    void refreshSpeedDistributions();
    void recordFrame(double msInterop, double msRender);
    void finish();  // commits the observables file
    // An interrupted run: a last observables row for the current step (unless it has one).
    void observeNow();

    const ObservableHistory& history() const { return m_history; }
    const SpeedDistributionData& speeds() const { return m_speeds; }
    const PerformanceData& performance() const { return m_performance; }
    const std::vector<RecoveryEvent>& recoveries() const { return m_recoveries; }
    const SpeedAccuracyData& speedAccuracy() const { return m_accuracy; }
    std::string status;

private:
    void observe(int64_t stepsSinceLast);
    void noteForceModel();
    void stepOnce();
    void keepRecoveryPoint(bool force);
    void recoverFrom(const InstabilityError& error);
    void trackAccuracy();

    LiveRunOptions m_options;
    Session m_session;
    LiveControls m_controls;
    DisplaySettings m_display;
    ObservableHistory m_history;
    SpeedDistributionData m_speeds;
    PerformanceData m_performance;
    std::unique_ptr<ObservablesOutput> m_observables;
    std::optional<BlowUpRecovery> m_recovery;
    uint64_t m_recoveryGeneration = 0;  // the session generation the recovery point belongs to
    std::vector<RecoveryEvent> m_recoveries;
    // The running setting's point of the speed-vs-accuracy panel: its samples of the conserved sum
    // (relative to the energy scale) since it started, and the force passes and time at its start.
    struct AccuracySegment {
        std::string label;
        uint64_t generation = 0;
        int64_t passes0 = 0;
        double time0 = 0;
        std::vector<double> times, energies;
    };
    SpeedAccuracyData m_accuracy;
    AccuracySegment m_segment;
    ObservablesRow m_lastRow;
    int64_t m_lastObservedStep = 0;
    double m_conserved0 = 0;
    std::chrono::steady_clock::time_point m_rateStart;
    int64_t m_rateSteps = 0, m_rateFrames = 0;
    double m_stepSeconds = 0, m_observeSeconds = 0, m_forceSeconds = 0, m_integrateSeconds = 0, m_collideSeconds = 0;
};

}  // namespace corebox
