// Writing scene files: sceneToToml and saveScene (scene_io.h). Hand-written rather than toml++'s
// formatter, to keep the sections in the documented order and every double in its shortest
// round-trip form, so that parseScene(sceneToToml(s)) gives back s exactly.
#include "scene_io.h"

#include <algorithm>
#include <charconv>
#include <climits>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "atomic_file.h"
#include "errors.h"

namespace corebox {
namespace {

namespace fs = std::filesystem;

// Shortest text that reads back to the same double, always with a '.' or exponent so that TOML
// keeps it a float.
std::string number(double value) {
    char buffer[64];
    auto [end, error] = std::to_chars(buffer, buffer + sizeof buffer, value);
    (void)error;  // 64 chars always suffice for a double
    std::string text(buffer, end);
    if (text.find_first_of(".eEn") == std::string::npos) text += ".0";  // 'n': inf, nan
    return text;
}

std::string quoted(const std::string& text) {
    std::string out = "\"";
    for (char c : text) {
        unsigned char u = static_cast<unsigned char>(c);
        if (c == '"' || c == '\\') {
            out += '\\';
            out += c;
        } else if (u < 0x20 || u == 0x7f) {
            char escape[8];
            std::snprintf(escape, sizeof escape, "\\u%04x", u);
            out += escape;
        } else {
            out += c;
        }
    }
    return out + "\"";
}

template <size_t N, class T>
std::string numberList(const std::array<T, N>& values) {
    std::string out = "[";
    for (size_t i = 0; i < N; ++i) out += (i ? ", " : "") + number(values[i]);
    return out + "]";
}

std::string hexColor(const std::array<float, 3>& color) {
    char text[8];
    int c[3];
    for (int i = 0; i < 3; ++i) {
        float unit = std::isnan(color[i]) ? 0.0f : std::clamp(color[i], 0.0f, 1.0f);
        c[i] = static_cast<int>(std::lround(unit * 255.0));
    }
    std::snprintf(text, sizeof text, "#%02x%02x%02x", c[0], c[1], c[2]);
    return text;
}

}  // namespace

std::string sceneToToml(const Scene& scene) {
    std::ostringstream out;
    out << "# corebox scene (reduced units: sigma, epsilon and mass of species 0)\n\n";

    out << "[box]\n"
        << "size = " << numberList(scene.box.size) << "\n"
        << "wall_restitution = " << number(scene.box.wallRestitution) << "\n";

    for (const SpeciesDef& s : scene.species) {
        out << "\n[[species]]\n"
            << "name = " << quoted(s.name) << "\n"
            << "count = " << s.count << "\n"
            << "mass = " << number(s.mass) << "\n"
            << "radius = " << number(s.radius) << "\n"
            << "sigma = " << number(s.sigma) << "\n"
            << "epsilon = " << number(s.epsilon) << "\n"
            << "color = \"" << hexColor(s.color) << "\"\n";
        if (s.acceleration != std::array<double, 3>{0, 0, 0}) out << "acceleration = " << numberList(s.acceleration) << "\n";
    }

    const InteractionDef& in = scene.interaction;
    out << "\n[interaction]\n";
    if (!in.mixing.empty()) {
        out << "mixing = [";
        for (size_t i = 0; i < in.mixing.size(); ++i) {
            out << (i ? ", " : "") << "[";
            for (size_t j = 0; j < in.mixing[i].size(); ++j) out << (j ? ", " : "") << number(in.mixing[i][j]);
            out << "]";
        }
        out << "]\n";
    }
    out << "cutoff = " << number(in.cutoff) << "\n"
        << "shift = " << quoted(shiftName(in.shift)) << "\n"
        << "restitution = " << number(in.restitution) << "\n"
        << "gravity = " << numberList(in.gravity) << "\n"
        << "elastic_below_speed = " << number(in.elasticBelowSpeed) << "\n"
        << "max_collision_rounds = " << in.maxCollisionRounds << "\n"
        << "contact_sweeps = " << in.contactSweeps << "\n"
        << "contact_listings = " << in.contactListings << "\n"
        << "forces = " << quoted(forceModelName(in.forces)) << "\n"
        << "skin = " << number(in.skin) << "\n";

    const IntegratorDef& integrator = scene.integrator;
    out << "\n[integrator]\n"
        << "method = " << quoted(integrator.automatic ? "auto" : methodName(integrator.method)) << "\n"
        << "dt = " << number(integrator.dt) << "\n"
        << "precision = " << quoted(precisionName(integrator.precision)) << "\n"
        << "adaptive = " << (integrator.adaptive ? "true" : "false") << "\n"
        << "tolerance = " << number(integrator.tolerance) << "\n";

    out << "\n[thermostat]\n"
        << "kind = " << quoted(thermostatName(scene.thermostat.kind)) << "\n"
        << "temperature = " << number(scene.thermostat.temperature) << "\n"
        << "tau = " << number(scene.thermostat.tau) << "\n";

    // TOML integers are signed 64-bit; a larger seed would come back negative and be rejected.
    if (scene.init.seed > static_cast<uint64_t>(INT64_MAX)) {
        throw InputError(locatedMessage(scene.sourcePath, 0, "init.seed", "must be < 2^63 to be written as TOML"));
    }
    out << "\n[init]\n"
        << "temperature = " << number(scene.init.temperature) << "\n"
        << "seed = " << scene.init.seed << "\n"
        << "placement = " << quoted(placementTable().name(scene.init.placement)) << "\n";
    if (!scene.init.particlesFile.empty()) out << "particles = " << quoted(scene.init.particlesFile) << "\n";

    out << "\n[devices]\n"
        << "gpus = " << (scene.devices.gpus > 0 ? std::to_string(scene.devices.gpus) : quoted("auto")) << "\n"
        << "exchange = " << quoted(exchangeName(scene.devices.exchange)) << "\n";
    return out.str();
}

void saveScene(const Scene& scene, const std::string& path) {
    Scene copy = scene;
    fs::path particles(scene.init.particlesFile);
    if (!particles.empty() && particles.is_relative()) {
        fs::path directory = fs::absolute(fs::path(path)).parent_path();
        copy.init.particlesFile = fs::absolute(particles).lexically_proximate(directory).string();
    }
    AtomicFile file(path);
    file.stream() << sceneToToml(copy);
    file.commit();
}

}  // namespace corebox
