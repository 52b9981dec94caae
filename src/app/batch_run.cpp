#include "batch_run.h"

#include <cstdio>
#include <memory>
#include <optional>

#include "blow_up_recovery.h"
#include "checkpoint.h"
#include "error_report.h"
#include "errors.h"
#include "initial_conditions.h"
#include "interruption.h"
#include "observables_output.h"
#include "progress.h"
#include "state_csv.h"

namespace corebox {

int runBatch(const RunOptions& options, const Scene& scene) {
    std::unique_ptr<Simulation> sim;
    std::unique_ptr<ObservablesOutput> observables;
    int exitCode = kExitOk;
    auto body = [&] {
        SimulationLimits limits;
        limits.maxEnergyDrift = options.maxEnergyDrift;
        if (options.restartPath.empty()) {
            const ParticleState initial = makeInitialState(scene, setupProgressLines(!options.quiet));
            sim = std::make_unique<Simulation>(scene, makeBackend(backendChoiceFor(scene, options.backend)), initial, limits);
        } else {
            const SimulationCheckpoint checkpoint = readCheckpoint(options.restartPath);
            sim = std::make_unique<Simulation>(scene, makeBackend(backendChoiceFor(scene, options.backend)), checkpoint, limits);
        }
        const Backend& backend = sim->backend();  // for the start line only (a recovery replaces it)
        const int64_t first = sim->stepIndex();  // 0, or the checkpoint's step
        if (first > options.steps)
            throw InputError("--restart: the checkpoint is at step " + std::to_string(first) + ", beyond --steps " +
                             std::to_string(options.steps) + " (--steps counts the whole run)");
        if (!options.quiet) {
            std::fprintf(stderr, "[corebox] %s: %lld particles, %zu species, %s %s dt = %g, backend %s (%s), %lld steps%s\n",
                         options.scenePath.empty() ? options.restartPath.c_str() : options.scenePath.c_str(),
                         (long long)sim->particleCount(), scene.species.size(), methodName(scene.integrator.method),
                         precisionName(scene.integrator.precision), scene.integrator.dt, backend.name().c_str(),
                         backend.deviceName().c_str(), (long long)options.steps,
                         first > 0 ? (", going on from step " + std::to_string(first)).c_str() : "");
        }
        if (!options.quiet) std::fprintf(stderr, "[corebox] forces: %s\n", sim->forceChoice().summary().c_str());
        observables = std::make_unique<ObservablesOutput>(options.observablesPath);
        auto writeCheckpointNow = [&] {
            if (options.checkpointPath.empty()) return;
            writeCheckpoint(options.checkpointPath, sim->checkpoint());
        };

        observables->header(sim->scene());
        ProgressReporter progress(options.steps, !options.quiet);
        const double dof = 3.0 * double(std::max<int64_t>(sim->particleCount(), 1));
        int64_t capHitsReported = 0;
        // A restarted run's rows go on after the checkpoint's step (the row at that step, if any, is in
        // the first run's file).
        if (first == 0) observables->row(sim->observe());
        // --recover: a recovery point at every row (blow_up_recovery.h), the rows held until the next.
        std::optional<BlowUpRecovery> recovery;
        if (options.recover) {
            recovery.emplace();
            recovery->remember(*sim);
            observables->hold();
        }
        auto rowNow = [&] {
            observables->row(sim->observe());
            if (recovery && recovery->rememberIfDue(*sim)) observables->release();
        };
        int64_t lastRow = first;
        for (int64_t s = first + 1; s <= options.steps && !interruptRequested(); ++s) {
            try {
                sim->step();
                // A checkpoint carries what the rows have not reported yet: it follows the regular rows
                // (every K steps, which a run that never stopped writes too) and precedes the extra row
                // at the end of this run (which such a run does not write).
                const bool regularRow = s % options.every == 0;
                if (regularRow) {
                    rowNow();
                    lastRow = s;
                }
                if (s == options.steps || (options.checkpointEvery > 0 && s % options.checkpointEvery == 0)) writeCheckpointNow();
                if (!regularRow && s == options.steps) {
                    rowNow();
                    lastRow = s;
                }
            } catch (const InstabilityError& e) {
                if (!recovery) throw;
                const RecoveryEvent event = recovery->recover(
                    sim, e, [&](const Scene& running) { return makeBackend(backendChoiceFor(running, options.backend)); });
                observables->discardAfter(event.resumedStep);
                lastRow = event.resumedStep;
                s = event.resumedStep;  // the loop goes on from the step after it
                std::fprintf(stderr, "[corebox] recovered from a blow-up at %s\n", event.summary().c_str());
                continue;
            }
            if (sim->roundCapHits() > capHitsReported) {
                std::fprintf(stderr, "[corebox] warning: step %lld: overlaps remained after %d collision rounds (%lld steps so far); "
                             "consider a smaller dt or a larger [interaction] max_collision_rounds\n",
                             (long long)s, sim->scene().interaction.maxCollisionRounds, (long long)sim->roundCapHits());
                capHitsReported = sim->roundCapHits() * 2;  // report again only when it keeps happening
            }
            progress.update(s, sim->time(), 2.0 * sim->lastKineticEnergy() / dof);
        }
        if (interruptRequested()) {
            // The step in progress has finished: the table ends at the current state, which is kept.
            const int64_t step = sim->stepIndex();
            writeCheckpointNow();  // before the row below resets the counters it carries
            if (step != lastRow) observables->row(sim->observe());
            observables->commit();
            const std::string statePath = interruptedStatePath(options);
            writeStateCsv(statePath, sim->state());
            std::fprintf(stderr, "[corebox] %s: stopped after step %lld of %lld; observables in %s, state in %s%s\n", interruptName(),
                         (long long)step, (long long)options.steps, observables->where().c_str(), statePath.c_str(),
                         options.checkpointPath.empty() ? "" : (", checkpoint in " + options.checkpointPath).c_str());
            exitCode = interruptExitCode();
            return;
        }
        progress.finish(options.steps, sim->time(), 2.0 * sim->lastKineticEnergy() / dof);
        if (first == options.steps) writeCheckpointNow();  // nothing left to run: the checkpoint as read
        if (!options.quiet) {
            const ForceCounters c = sim->backend().forceCounters();
            std::fprintf(stderr, "[corebox] forces: %s; %lld force passes, %lld refreshes after collisions, %lld neighbour-list builds\n",
                         forceModelName(sim->forceChoice().model), (long long)c.fullPasses, (long long)c.refreshes, (long long)c.listBuilds);
            if (recovery && recovery->recoveries() > 0)
                std::fprintf(stderr, "[corebox] %d recoveries from blow-ups; the run ended with %s dt = %g\n", recovery->recoveries(),
                             methodName(sim->scene().integrator.method), sim->scene().integrator.dt);
        }
        observables->commit();
        if (!options.stateOutPath.empty()) writeStateCsv(options.stateOutPath, sim->state());
    };
    auto afterInstability = [&] {
        if (!sim) return;
        keepAfterInstability(options, *sim, [&] {
            if (observables) observables->commit();
        });
    };
    const int code = runReportingErrors(body, afterInstability);
    return code != kExitOk ? code : exitCode;
}

}  // namespace corebox
