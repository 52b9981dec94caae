// The integration part of a step, written once for every backend: velocity Verlet and its symplectic
// compositions (symplectic_composition.h) with their cached accelerations, a fixed-step explicit
// Runge-Kutta method, or Dormand-Prince with its step-size controller (reject and retry until the
// embedded error estimate is within tolerance). The driver
// owns what outlives a step: the Butcher table (sent to the backend when the method changes), the
// next adaptive step size and whether the backend's cached accelerations still match its positions.
#pragma once

#include "backend.h"
#include "butcher_tableau.h"
#include "symplectic_composition.h"
#include "scene.h"
#include "step_report.h"

namespace corebox {

// Force evaluations per step of a fixed-step method: its stages, or a composition's kicks (Verlet: 1,
// its first-same-as-last kick reused).
int forcePassesPerStepOf(Method method);

// An adaptive step never exceeds this many times the scene's dt.
constexpr double kAdaptiveGrowthCap = 16;

class IntegrationDriver {
public:
    // Applies an integrator setting (at creation and on every live edit); a new dt restarts the
    // adaptive controller from it.
    void configure(Backend& backend, const IntegratorDef& integrator);
    // The backend's state changed behind the driver's back (new state, collisions, a new model):
    // Verlet's cached accelerations must be recomputed before they are used again.
    void invalidateAccelerations() { m_accelerationsValid = false; }
    // Whether the backend's A holds a(X) for the next kick (checkpoints), and its restoration.
    bool accelerationsValid() const { return m_accelerationsValid; }
    void restoreAccelerationsValid() { m_accelerationsValid = true; }

    // Advances the backend's state by one step; fills report.dt and report.rejectedSteps. Throws
    // InstabilityError when the adaptive controller cannot meet its tolerance.
    void integrate(Backend& backend, StepReport& report);

    // The adaptive controller's next step size (checkpoints), and its restoration after configure().
    double nextDt() const { return m_dtNext; }
    void restoreNextDt(double dt) {
        if (dt > 0) m_dtNext = dt;
    }
    // Shortens the adaptive controller's next step to at most dt (to land on a given time).
    void limitNextDt(double dt) {
        if (dt > 0 && dt < m_dtNext) m_dtNext = dt;
    }

private:
    void compositionStep(Backend& backend, double dt);
    void rkStep(Backend& backend, double dt, int stages);
    void adaptiveStep(Backend& backend, StepReport& report);

    IntegratorDef m_integrator;
    ButcherTableau m_tableau{};
    SymplecticComposition m_composition;  // verlet and its compositions
    bool m_configured = false;
    double m_dtNext = 0;
    bool m_accelerationsValid = false;
};

}  // namespace corebox
