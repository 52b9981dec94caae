// Maxwell-Boltzmann speed distribution in 3D, with a = sqrt(kT/m) (k_B = 1):
//   f(v) = 4 pi (m / (2 pi kT))^(3/2) v^2 exp(-m v^2 / (2 kT))   (the report's eq. 2 drops a 2)
//   F(v) = erf(v / (sqrt2 a)) - sqrt(2/pi) (v/a) exp(-v^2 / (2 a^2))
#pragma once

#include <cmath>

#include "hd.h"

namespace corebox {

COREBOX_HD inline double maxwellBoltzmannPdf(double speed, double mass, double temperature) {
    const double a2 = temperature / mass;
    const double norm = 4.0 * 3.14159265358979323846 * pow(2.0 * 3.14159265358979323846 * a2, -1.5);
    return norm * speed * speed * exp(-speed * speed / (2.0 * a2));
}

COREBOX_HD inline double maxwellBoltzmannCdf(double speed, double mass, double temperature) {
    if (speed <= 0) return 0;
    const double a = sqrt(temperature / mass);
    const double u = speed / a;
    return erf(u / 1.41421356237309504880) - 0.79788456080286535588 * u * exp(-0.5 * u * u);
}

// Several species at one temperature: F(v) = sum_k w_k F(v; m_k, T), weights w_k summing to one.
COREBOX_HD inline double maxwellBoltzmannMixtureCdf(double speed, const double* weights, const double* masses, int count,
                                                    double temperature) {
    double f = 0;
    for (int k = 0; k < count; ++k) {
        if (weights[k] > 0) f += weights[k] * maxwellBoltzmannCdf(speed, masses[k], temperature);
    }
    return f;
}

// Temperature that gives a sample's mean speed: <v> = sqrt(8 kT / (pi m)), so kT = pi m <v>^2 / 8.
// With several species (fractions w_k, masses m_k): <v> = sqrt(kT) sum_k w_k sqrt(8 / (pi m_k)).
COREBOX_HD inline double temperatureFromMeanSpeed(double meanSpeed, double mass) {
    return 3.14159265358979323846 * mass * meanSpeed * meanSpeed / 8.0;
}

}  // namespace corebox
