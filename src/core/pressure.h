// Pressure observables (issue 9): the pressure on the walls and the virial pressure of the whole box
// with collisions, each averaged over a window (the interval between observable rows).
//
//   wall:    P_wall = sum_walls I_w / (sum_walls A_w t)
//   virial:  P_virial = (2 <K> + W_pair + W_coll / t) / (3 V)
// I_w is the momentum wall w received in the window (impacts and resting contacts alike,
// impulse_sums.h), t the window's length, <K> the kinetic energy averaged over the window (end of
// each step, weighted by its dt), W_pair = sum_{i<j} r_ij . F_ij of the pair forces sampled at the
// row (an O(N^2) pass like the potential energy; 0 for pure hard spheres), W_coll = sum r_ij . J_ij
// over the window's pair impulses.
//
// Convention for area and volume: the region open to particle centres, [a, L_k - a] on each axis.
// A hard wall meets a centre only on that region's faces, so A_w is the face (L_j - 2a)(L_k - 2a)
// and V = prod_k (L_k - 2a). With these the two routes are one identity in the time average: the
// wall forces' virial is -3 P_wall V (a wall at a pushes with x = a, the one at L - a with
// x = L - a), so the virial theorem gives 3 P_wall V = 2 <K> + <W_pair> + W_coll / t, up to the
// boundary term (change of sum x.p over the window) / t. a is the hard-core radius; with several
// species, their mean radius by count (exact for one radius; for mixtures the routes then agree to
// O(spread of radii / L)). Under gravity the walls differ (the floor bears the weight); P_wall is
// their area-weighted mean, and ObservablesRow keeps each wall's momentum.
//
// Whole walls or their centres. Both routes above include the walls' edges, where the fluid's
// tangential stress next to one wall (its surface tension) pushes on the wall across it: a term of
// order gamma / L that is ~10% of the pressure for hard spheres at packing fraction 0.35 in a box of
// 14 diameters. The momentum given to the centre of each wall (impulse_sums.h: a quarter of its
// face, away from the edges) over that area is the bulk fluid's pressure without it:
//   centre:  P_wall_centre = sum_walls I_w,centre / (sum_walls A_w / 4 t).
#pragma once

#include <array>

#include "impulse_sums.h"
#include "scene.h"
#include "step_report.h"

namespace corebox {

struct PressureGeometry {
    std::array<double, 3> lengths{};             // L_k - 2a: the region open to centres [sigma]
    double volume = 0;                           // prod lengths [sigma^3]
    std::array<double, kWallCount> wallArea{};   // face of each wall, index 2 axis + side [sigma^2]
    double totalArea = 0;
};

PressureGeometry pressureGeometryOf(const Scene& scene);

// What a window of steps gave the pressure: its length, kinetic energy integral and impulses.
class PressureWindow {
public:
    void addStep(const StepReport& report, double kineticAfter);
    void reset() { *this = PressureWindow{}; }

    double time() const { return m_time; }
    double kineticTime() const { return m_kineticTime; }
    double meanKinetic() const { return m_time > 0 ? m_kineticTime / m_time : 0.0; }
    const ImpulseSums& impulses() const { return m_impulses; }
    // A window carried over by a checkpoint.
    void restore(double time, double kineticTime, const ImpulseSums& impulses) {
        m_time = time;
        m_kineticTime = kineticTime;
        m_impulses = impulses;
    }

    // 0 for an empty window (the row at step 0).
    double wallPressure(const PressureGeometry& g) const;
    double wallCentrePressure(const PressureGeometry& g) const;
    double virialPressure(const PressureGeometry& g, double pairVirial) const;

private:
    double m_time = 0;
    double m_kineticTime = 0;  // sum of K dt
    ImpulseSums m_impulses;
};

}  // namespace corebox
