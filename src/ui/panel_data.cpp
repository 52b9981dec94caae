#include "panel_data.h"

#include <algorithm>
#include <cmath>

namespace corebox {

namespace {
void append(std::vector<float>& series, double value, size_t capacity) {
    series.push_back(float(value));
    if (series.size() > capacity) series.erase(series.begin());
}
}  // namespace

void ObservableHistory::push(const ObservablesRow& row, double conserved0, double targetTemperature, int64_t stepsSinceLast) {
    append(time, row.time, m_capacity);
    append(kinetic, row.kinetic, m_capacity);
    append(potential, row.potential, m_capacity);
    append(total, row.total(), m_capacity);
    append(dissipated, row.dissipated, m_capacity);
    append(drift, conserved0 != 0 ? (row.conserved() - conserved0) / std::fabs(conserved0) : 0.0, m_capacity);
    append(temperature, row.temperature, m_capacity);
    append(target, targetTemperature, m_capacity);
    append(collisionsPerStep, stepsSinceLast > 0 ? double(row.collisionsPair + row.collisionsWall) / double(stepsSinceLast) : 0.0,
           m_capacity);
    if (row.window > 0) {
        append(pressureWall, row.pressureWall, m_capacity);
        append(pressureVirial, row.pressureVirial, m_capacity);
    }
}

void ObservableHistory::dropAfter(double t) {
    size_t drop = 0;
    while (drop < time.size() && double(time[time.size() - 1 - drop]) > t) ++drop;
    // The pressure series skip rows without a window, so they lose at most as many points.
    for (auto* s : {&time, &kinetic, &potential, &total, &dissipated, &drift, &temperature, &target, &collisionsPerStep, &pressureWall,
                    &pressureVirial})
        s->resize(s->size() - std::min(drop, s->size()));
}

void ObservableHistory::clear() {
    for (auto* s : {&time, &kinetic, &potential, &total, &dissipated, &drift, &temperature, &target, &collisionsPerStep, &pressureWall,
                    &pressureVirial})
        s->clear();
}

}  // namespace corebox
