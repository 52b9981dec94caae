#include "observables.h"

#include <cstdio>

#include "vocabulary.h"

namespace corebox {

std::string observablesHeader(const Scene& scene) {
    std::string header =
        "step,time,kinetic,potential,total,dissipated,thermostat,px,py,pz,temperature,collisions_pair,collisions_wall,pressure_wall,"
        "pressure_virial,pressure_wall_centre";
    for (const SpeciesDef& s : scene.species) header += ",temperature_" + s.name;
    return header + ",forces";
}

void writeObservablesRow(std::ostream& out, const ObservablesRow& row) {
    char buffer[512];
    std::snprintf(buffer, sizeof buffer, "%lld,%.10g,%.12g,%.12g,%.12g,%.12g,%.12g,%.6e,%.6e,%.6e,%.8g,%lld,%lld,%.8g,%.8g,%.8g",
                  (long long)row.step, row.time, row.kinetic, row.potential, row.total(), row.dissipated, row.thermostat, row.px,
                  row.py, row.pz, row.temperature, (long long)row.collisionsPair, (long long)row.collisionsWall, row.pressureWall,
                  row.pressureVirial, row.pressureWallCentre);
    out << buffer;
    for (double t : row.speciesTemperature) {
        std::snprintf(buffer, sizeof buffer, ",%.8g", t);
        out << buffer;
    }
    out << ',' << forceModelName(row.forces) << '\n';
}

}  // namespace corebox
