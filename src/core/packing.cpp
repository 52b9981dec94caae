#include "packing.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

namespace corebox {
namespace {

constexpr double kPi = 3.14159265358979323846;

std::string formatG(double value) {
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%.3g", value);
    return buffer;
}

// Rule 3: the lattice's spacing against the largest contact distance of the species present.
std::optional<PackingProblem> latticeProblem(const Scene& scene) {
    const std::array<int64_t, 3> sites = latticeSites(scene);
    double minDistance = 0;
    for (const SpeciesDef& a : scene.species) {
        if (a.count == 0) continue;
        for (const SpeciesDef& b : scene.species) {
            if (b.count > 0) minDistance = std::max(minDistance, a.radius + b.radius);
        }
    }
    for (int a = 0; a < 3; ++a) {
        const double spacing = scene.box.size[size_t(a)] / double(sites[size_t(a)]);
        if (spacing < minDistance) {
            std::ostringstream msg;
            msg << "more particles than fit: " << scene.particleCount() << " particles on a lattice in this box need a spacing of "
                << spacing << " on axis " << "xyz"[a] << ", below the largest contact distance " << minDistance
                << "; enlarge the box or use fewer or smaller particles";
            return PackingProblem{"species", msg.str()};
        }
    }
    return std::nullopt;
}

}  // namespace

std::array<int64_t, 3> latticeSites(const Scene& scene) {
    const int64_t n = scene.particleCount();
    const std::array<double, 3>& box = scene.box.size;
    const double density = double(n) / (box[0] * box[1] * box[2]);
    std::array<int64_t, 3> sites{};
    // L cbrt(n / V) is a whole number when the particles fill a cubic lattice exactly (343 in a cube,
    // 4^3 in bench forces' box); rounded up it may come out a part in 10^16 above it, and one site
    // too many shrinks the spacing below the contact distance: round a whole number down first.
    for (int a = 0; a < 3; ++a) {
        const double perAxis = box[size_t(a)] * std::cbrt(density);
        sites[size_t(a)] = std::max<int64_t>(1, int64_t(std::ceil(perAxis * (1.0 - 1e-12))));
    }
    while (sites[0] * sites[1] * sites[2] < n) {
        int widest = 0;
        for (int a = 1; a < 3; ++a) {
            if (box[size_t(a)] / double(sites[size_t(a)]) > box[size_t(widest)] / double(sites[size_t(widest)])) widest = a;
        }
        ++sites[size_t(widest)];
    }
    return sites;
}

std::optional<PackingProblem> packingProblem(const Scene& scene) {
    const auto& size = scene.box.size;
    const double smallestEdge = *std::min_element(size.begin(), size.end());
    double coreVolume = 0;
    for (size_t i = 0; i < scene.species.size(); ++i) {
        const SpeciesDef& s = scene.species[i];
        if (2 * s.radius > smallestEdge) {
            return PackingProblem{"species[" + std::to_string(i) + "].radius",
                                  "diameter " + formatG(2 * s.radius) + " exceeds the smallest box edge " + formatG(smallestEdge)};
        }
        coreVolume += static_cast<double>(s.count) * 4.0 / 3.0 * kPi * s.radius * s.radius * s.radius;
    }
    const double fraction = coreVolume / (size[0] * size[1] * size[2]);
    if (fraction > kMaxPackingFraction) {
        return PackingProblem{"species", "more particles than fit: hard-core packing fraction " + formatG(fraction) + " exceeds the limit " +
                                             formatG(kMaxPackingFraction) + "; enlarge box.size or lower the counts"};
    }
    if (scene.init.placement == Placement::Lattice && scene.init.particlesFile.empty()) return latticeProblem(scene);
    return std::nullopt;
}

}  // namespace corebox
