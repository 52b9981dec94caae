// Observables of a run (DESIGN.md sec. 3) and their CSV form. Collision counts in a row are those
// since the previous row, and so are the pressures (pressure.h: averaged over that window; 0 in the
// row at step 0). The conserved sum E_kin + E_pot + E_dissipated - E_thermostat stays
// constant up to integration error: it is what the blow-up check and the energy tests watch. The
// last column, `forces`, names the pair-force model the run used at the row (the automatic choice or
// the scene's; a live edit that changes it shows from the next row on).
#pragma once

#include <cstdint>
#include <ostream>
#include <string>
#include <vector>

#include "impulse_sums.h"
#include "scene.h"

namespace corebox {

struct ObservablesRow {
    int64_t step = 0;
    double time = 0;
    double kinetic = 0;
    double potential = 0;
    double dissipated = 0;   // cumulative kinetic energy lost in inelastic collisions
    double thermostat = 0;   // cumulative energy given by the thermostat
    double px = 0, py = 0, pz = 0;
    double temperature = 0;
    int64_t collisionsPair = 0;
    int64_t collisionsWall = 0;
    double pressureWall = 0;    // momentum given to the walls per area and time [eps / sigma^3]
    double pressureVirial = 0;  // kinetic + pair-force virial + collision virial [eps / sigma^3]
    double pressureWallCentre = 0;  // as pressureWall over the walls' centres, away from their edges
    double window = 0;          // time since the previous row [tau]
    ImpulseSums impulses;       // of that window: each wall's momentum, r_ij . J_ij of the pair impulses
    std::vector<double> speciesTemperature;
    ForceModel forces = ForceModel::AllPairs;  // the pair-force model in effect (force_model.h): none, all_pairs, neighbour_list

    double total() const { return kinetic + potential; }
    double conserved() const { return kinetic + potential + dissipated - thermostat; }
};

std::string observablesHeader(const Scene& scene);
void writeObservablesRow(std::ostream& out, const ObservablesRow& row);

}  // namespace corebox
