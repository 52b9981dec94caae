#include "memory_estimate.h"


#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "errors.h"
#include "symplectic_composition.h"

namespace corebox {
double latticeSiteCount(const Scene& scene) {
    if (scene.init.placement != Placement::Lattice || !scene.init.particlesFile.empty()) return 0;
    const double n = double(scene.particleCount());
    const auto& box = scene.box.size;
    const double density = n / (box[0] * box[1] * box[2]);
    double sites = 1;
    for (double l : box) sites *= std::max(1.0, std::ceil(l * std::cbrt(density)));
    return std::max(sites, n);
}

double estimatedHostBytes(const Scene& scene) {
    const double n = double(scene.particleCount());
    const double real = scene.integrator.precision == Precision::Fp32 ? 4 : 8;
    const double stages = isComposition(scene.integrator.method) ? 1 : double(tableauFor(scene.integrator.method).stages);
    // State as double (x, v: 48 bytes, species 4) three times (initial, current, last good); the
    // backend's x, v, acceleration, stage x and v (5 x 3 reals), k_x and k_v per stage, contact
    // acceleration; events, flags, losses and the cell list (about 64 bytes).
    const double perParticle = 3 * 52 + (6 + 6 * stages) * 3 * real + 64;
    return n * perParticle + 8 * latticeSiteCount(scene);
}

double physicalMemoryBytes() {
    const long pages = ::sysconf(_SC_PHYS_PAGES), pageSize = ::sysconf(_SC_PAGESIZE);
    return pages > 0 && pageSize > 0 ? double(pages) * double(pageSize) : 0.0;
}

std::string formatBytes(double bytes) {
    const char* units[] = {"B", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB"};
    int u = 0;
    while (bytes >= 1024 && u < 6) {
        bytes /= 1024;
        ++u;
    }
    char text[64];
    std::snprintf(text, sizeof text, u == 6 && bytes >= 1024 ? "%.3g %s" : "%.1f %s", bytes, units[u]);
    return text;
}

void checkHostMemory(const Scene& scene) {
    const double need = estimatedHostBytes(scene), have = physicalMemoryBytes();
    if (have <= 0 || need <= have) return;
    const double sites = latticeSiteCount(scene), n = double(scene.particleCount());
    std::string why = std::to_string(scene.particleCount()) + " particles need about " + formatBytes(need) + " of memory";
    if (8 * sites > need / 2) {
        char count[32];
        std::snprintf(count, sizeof count, "%.3g", sites);
        why += ", mostly for the " + std::string(count) +
               " sites of the lattice placement in this box (one edge much longer than the others); use placement = \"random\", "
               "or a box closer to a cube,";
    } else {
        why += " (about " + formatBytes(need / std::max(n, 1.0)) + " each); use fewer particles,";
    }
    throw InputError(locatedMessage(scene.sourcePath, 0, "species", why + " this machine has " + formatBytes(have)));
}

}  // namespace corebox
