#include "batch_run.h"

#include <cstdio>
#include <iostream>
#include <memory>

#include "atomic_file.h"
#include "error_report.h"
#include "initial_conditions.h"
#include "observables.h"
#include "progress.h"
#include "state_csv.h"

namespace corebox {

int runBatch(const RunOptions& options, const Scene& scene) {
    std::unique_ptr<Simulation> sim;
    std::unique_ptr<AtomicFile> observablesFile;
    auto body = [&] {
        const ParticleState initial = makeInitialState(scene);
        std::unique_ptr<Backend> backend = makeBackend(backendChoiceFor(scene, options.backend));
        std::fprintf(stderr, "[corebox] %s: %lld particles, %zu species, %s %s dt = %g, backend %s (%s), %lld steps\n",
                     options.scenePath.c_str(), (long long)initial.size(), scene.species.size(), methodName(scene.integrator.method),
                     precisionName(scene.integrator.precision), scene.integrator.dt, backend->name().c_str(),
                     backend->deviceName().c_str(), (long long)options.steps);
        SimulationLimits limits;
        limits.maxEnergyDrift = options.maxEnergyDrift;
        sim = std::make_unique<Simulation>(scene, std::move(backend), initial, limits);
        if (!options.observablesPath.empty()) observablesFile = std::make_unique<AtomicFile>(options.observablesPath);

        std::ostream& out = observablesFile ? observablesFile->stream() : std::cout;
        out << observablesHeader(sim->scene()) << '\n';
        ProgressReporter progress(options.steps, !options.quiet);
        const double dof = 3.0 * double(std::max<int64_t>(sim->particleCount(), 1));
        int64_t capHitsReported = 0;
        writeObservablesRow(out, sim->observe());
        for (int64_t s = 1; s <= options.steps; ++s) {
            sim->step();
            if (s % options.every == 0 || s == options.steps) writeObservablesRow(out, sim->observe());
            if (sim->roundCapHits() > capHitsReported) {
                std::fprintf(stderr, "[corebox] warning: step %lld: overlaps remained after %d collision rounds (%lld steps so far); "
                             "consider a smaller dt or a larger [interaction] max_collision_rounds\n",
                             (long long)s, sim->scene().interaction.maxCollisionRounds, (long long)sim->roundCapHits());
                capHitsReported = sim->roundCapHits() * 2;  // report again only when it keeps happening
            }
            progress.update(s, sim->time(), 2.0 * sim->lastKineticEnergy() / dof);
        }
        progress.finish(options.steps, sim->time(), 2.0 * sim->lastKineticEnergy() / dof);
        if (observablesFile) observablesFile->commit();
        if (!options.stateOutPath.empty()) writeStateCsv(options.stateOutPath, sim->state());
    };
    auto afterInstability = [&] {
        if (!sim) return;
        keepAfterInstability(options, *sim, [&] {
            if (observablesFile) observablesFile->commit();
        });
    };
    return runReportingErrors(body, afterInstability);
}

}  // namespace corebox
