// The integration part of one step, the same on every backend: velocity Verlet, a fixed-step
// Runge-Kutta method, or Dormand-Prince with its step-size controller (rejecting and retrying until
// the embedded error estimate is within tolerance). Backends supply the arithmetic through four
// hooks: verletStep(dt), rkStep(dt, stages) (solution into the stage buffers), embeddedError(dt,
// tolerance) (RMS of the scaled error of the last rkStep) and acceptStage() (stage buffers become
// the state).
#pragma once

#include <string>

#include "backend.h"
#include "butcher_tableau.h"
#include "errors.h"
#include "rk_stage.h"
#include "scene.h"

namespace corebox {

template <class Hooks>
void integrateStep(Hooks& hooks, const IntegratorDef& integrator, const ButcherTableau& tableau, double& dtNext, StepReport& report) {
    if (integrator.method == Method::Verlet) {
        report.dt = integrator.dt;
        hooks.verletStep(integrator.dt);
        return;
    }
    if (!integrator.adaptive || tableau.embeddedOrder == 0) {
        report.dt = integrator.dt;
        hooks.rkStep(integrator.dt, tableau.solutionStages);
        hooks.acceptStage();
        return;
    }
    double dt = dtNext;
    for (int attempt = 0;; ++attempt) {
        hooks.rkStep(dt, tableau.stages);
        const double error = hooks.embeddedError(dt, integrator.tolerance);
        const double factor = adaptiveStepFactor(error, tableau.embeddedOrder);
        if (error <= 1.0) {
            report.dt = dt;
            report.rejectedSteps = attempt;
            dtNext = dt * factor;
            hooks.acceptStage();
            return;
        }
        dt *= factor;
        if (attempt >= 60 || dt < 1e-12 * integrator.dt) {
            throw InstabilityError("adaptive dp5 could not meet tolerance " + std::to_string(integrator.tolerance) +
                                   ": step size fell to " + std::to_string(dt) + " after " + std::to_string(attempt + 1) +
                                   " rejected attempts");
        }
    }
}

}  // namespace corebox
