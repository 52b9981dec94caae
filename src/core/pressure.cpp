#include "pressure.h"

#include <algorithm>

namespace corebox {

PressureGeometry pressureGeometryOf(const Scene& scene) {
    double radiusSum = 0, count = 0;
    for (const SpeciesDef& s : scene.species) {
        radiusSum += double(s.count) * s.radius;
        count += double(s.count);
    }
    const double a = count > 0 ? radiusSum / count : 0.0;
    PressureGeometry g;
    for (int k = 0; k < 3; ++k) g.lengths[size_t(k)] = std::max(scene.box.size[size_t(k)] - 2 * a, 0.0);
    g.volume = g.lengths[0] * g.lengths[1] * g.lengths[2];
    for (int axis = 0; axis < 3; ++axis) {
        const double face = g.lengths[size_t((axis + 1) % 3)] * g.lengths[size_t((axis + 2) % 3)];
        g.wallArea[size_t(2 * axis)] = g.wallArea[size_t(2 * axis + 1)] = face;
        g.totalArea += 2 * face;
    }
    return g;
}

void PressureWindow::addStep(const StepReport& report, double kineticAfter) {
    m_time += report.dt;
    m_kineticTime += kineticAfter * report.dt;
    m_impulses += report.impulses;
}

double PressureWindow::wallPressure(const PressureGeometry& g) const {
    if (!(m_time > 0) || !(g.totalArea > 0)) return 0;
    return m_impulses.wallTotal() / (g.totalArea * m_time);
}

double PressureWindow::wallCentrePressure(const PressureGeometry& g) const {
    if (!(m_time > 0) || !(g.totalArea > 0)) return 0;
    double centre = 0;
    for (double impulse : m_impulses.wallCentre) centre += impulse;
    return centre / (0.25 * g.totalArea * m_time);  // the middle half of both tangential extents
}

double PressureWindow::virialPressure(const PressureGeometry& g, double pairVirial) const {
    if (!(m_time > 0) || !(g.volume > 0)) return 0;
    return (2 * meanKinetic() + pairVirial + m_impulses.pairVirial / m_time) / (3 * g.volume);
}

}  // namespace corebox
