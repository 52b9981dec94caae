// Reference results for the elastic hard-sphere fluid (diameter sigma, mass m, k_B T), used by the
// dense hard-sphere tests and `corebox bench hardspheres` to judge the measured pressure and
// collision rate. phi = n pi sigma^3 / 6 is the packing fraction of number density n.
//
//   Carnahan-Starling (1969):  Z = P / (n kT) = (1 + phi + phi^2 - phi^3) / (1 - phi)^3
//   contact value of g(r) consistent with it, through Z = 1 + 4 phi g(sigma):
//                              g(sigma) = (1 - phi/2) / (1 - phi)^3
//   Enskog collision frequency per particle:
//                              Gamma = 4 n sigma^2 sqrt(pi kT / m) g(sigma)
//   (pair collisions per unit time in a homogeneous fluid of N particles: N Gamma / 2).
// Mean impulse per collision: for equal masses the normal speed of a colliding pair is distributed as
// vn exp(-m vn^2 / (4 kT)), so <|J|> = m <vn> = sqrt(pi m kT); with the rate this gives the
// collision part of the virial, 3 N kT (Z - 1) per unit time: the two formulas above agree.
#pragma once

#include <cmath>

#include "hd.h"

namespace corebox {

COREBOX_HD inline double carnahanStarlingZ(double phi) {
    const double d = 1.0 - phi;
    return (1.0 + phi + phi * phi - phi * phi * phi) / (d * d * d);
}

COREBOX_HD inline double carnahanStarlingContactValue(double phi) {
    const double d = 1.0 - phi;
    return (1.0 - 0.5 * phi) / (d * d * d);
}

COREBOX_HD inline double packingFractionOf(double numberDensity, double sigma) {
    return numberDensity * 3.14159265358979323846 * sigma * sigma * sigma / 6.0;
}

COREBOX_HD inline double enskogCollisionFrequency(double numberDensity, double sigma, double temperature, double mass) {
    const double phi = packingFractionOf(numberDensity, sigma);
    return 4.0 * numberDensity * sigma * sigma * sqrt(3.14159265358979323846 * temperature / mass) *
           carnahanStarlingContactValue(phi);
}

}  // namespace corebox
