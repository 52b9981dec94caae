#include "integration_driver.h"

#include <algorithm>
#include <string>

#include "errors.h"
#include "rk_stage.h"

namespace corebox {

int forcePassesPerStepOf(Method method) {
    return isComposition(method) ? forcePassesPerStep(compositionFor(method)) : tableauFor(method).solutionStages;
}

void IntegrationDriver::configure(Backend& backend, const IntegratorDef& integrator) {
    if (!m_configured || integrator.dt != m_integrator.dt || m_dtNext <= 0) m_dtNext = integrator.dt;
    m_integrator = integrator;
    m_configured = true;
    if (isComposition(integrator.method)) {
        m_composition = compositionFor(integrator.method);
    } else {
        m_tableau = tableauFor(integrator.method);
        backend.setTableau(m_tableau);
    }
    m_accelerationsValid = false;
}

void IntegrationDriver::integrate(Backend& backend, StepReport& report) {
    if (isComposition(m_integrator.method)) {
        report.dt = m_integrator.dt;
        compositionStep(backend, m_integrator.dt);
    } else if (!m_integrator.adaptive || m_tableau.embeddedOrder == 0) {
        report.dt = m_integrator.dt;
        rkStep(backend, m_integrator.dt, m_tableau.solutionStages);
        backend.acceptStage();
    } else {
        adaptiveStep(backend, report);
    }
}

// Drifts and kicks in the composition's order. A kick needs a(x) at the current positions: a force
// pass when a drift (or anything outside the driver) moved them since the last one. Verlet's kick at
// the end of a step is the next step's first: one force pass per step unless something moved the
// particles in between.
// A kick right after a force pass, and a drift right after a kick, go to the backend as one call
// (Backend::accelerateAndKick, kickDrift): the same arithmetic in fewer passes.
void IntegrationDriver::compositionStep(Backend& backend, double dt) {
    const std::vector<CompositionOp>& ops = m_composition.ops;
    for (size_t k = 0; k < ops.size(); ++k) {
        const CompositionOp& op = ops[k];
        if (op.kind == CompositionOp::Drift) {
            backend.drift(op.weight * dt);
            m_accelerationsValid = false;
            continue;
        }
        const double h = op.weight * dt;
        const bool driftNext = k + 1 < ops.size() && ops[k + 1].kind == CompositionOp::Drift;
        if (!m_accelerationsValid && !driftNext) {
            backend.accelerateAndKick(h);
            m_accelerationsValid = true;
            continue;
        }
        if (!m_accelerationsValid) backend.computeAccelerations();
        m_accelerationsValid = true;
        if (!driftNext) {
            backend.kick(h);
            continue;
        }
        backend.kickDrift(h, ops[k + 1].weight * dt);
        m_accelerationsValid = false;
        ++k;
    }
}

void IntegrationDriver::rkStep(Backend& backend, double dt, int stages) { backend.rkStep(stages, dt); }

void IntegrationDriver::adaptiveStep(Backend& backend, StepReport& report) {
    double dt = m_dtNext;
    for (int attempt = 0;; ++attempt) {
        rkStep(backend, dt, m_tableau.stages);
        const double error = backend.rkErrorNorm(dt, m_integrator.tolerance);
        const double factor = adaptiveStepFactor(error, m_tableau.embeddedOrder);
        if (error <= 1.0) {
            report.dt = dt;
            report.rejectedSteps = attempt;
            // The error estimate sees only the smooth forces: under gravity alone it is zero and the
            // step would grow until balls pass through each other and the walls. The cap keeps the
            // collision stage's work bounded.
            m_dtNext = std::min(dt * factor, kAdaptiveGrowthCap * m_integrator.dt);
            backend.acceptStage();
            return;
        }
        dt *= factor;
        if (attempt >= 60 || dt < 1e-12 * m_integrator.dt) {
            throw InstabilityError("adaptive dp5 could not meet tolerance " + std::to_string(m_integrator.tolerance) +
                                   ": step size fell to " + std::to_string(dt) + " after " + std::to_string(attempt + 1) +
                                   " rejected attempts");
        }
    }
}

}  // namespace corebox
