#include "scene_io.h"

#include <toml++/toml.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <climits>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <sstream>
#include <utility>

#include "atomic_file.h"
#include "errors.h"

namespace corebox {
namespace {

namespace fs = std::filesystem;

// Above ~0.45 random placement stalls and a simple cubic lattice (max 0.52) barely fits; such a
// scene is a typo in a count or a box size far more often than an intent.
constexpr double kMaxPackingFraction = 0.45;

constexpr double kPi = 3.14159265358979323846;

const char* const kRootKeys[] = {"box", "species", "interaction", "integrator", "thermostat", "init"};
const char* const kBoxKeys[] = {"size", "wall_restitution"};
const char* const kSpeciesKeys[] = {"name", "count", "mass", "radius", "sigma", "epsilon", "color"};
const char* const kInteractionKeys[] = {"mixing",      "cutoff",  "shift", "restitution", "gravity", "elastic_below_speed",
                                        "max_collision_rounds"};
const char* const kIntegratorKeys[] = {"method", "dt", "precision", "adaptive", "tolerance"};
const char* const kThermostatKeys[] = {"kind", "temperature", "tau"};
const char* const kInitKeys[] = {"temperature", "seed", "placement", "particles"};

// Colours for species that give none, by position: distinct under the renderer's shading.
const char* const kPalette[] = {"#cc4d33", "#3373cc", "#4dad4d", "#d9a626", "#8c4dbf", "#33b3b3"};

std::string joined(const char* const* names, size_t count) {
    std::string out;
    for (size_t i = 0; i < count; ++i) out += (i ? ", " : "") + std::string(names[i]);
    return out;
}

size_t editDistance(const std::string& a, const std::string& b) {
    std::vector<size_t> row(b.size() + 1);
    for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
    for (size_t i = 1; i <= a.size(); ++i) {
        size_t diagonal = row[0];
        row[0] = i;
        for (size_t j = 1; j <= b.size(); ++j) {
            size_t substitute = diagonal + (a[i - 1] == b[j - 1] ? 0 : 1);
            diagonal = row[j];
            row[j] = std::min({row[j] + 1, row[j - 1] + 1, substitute});
        }
    }
    return row[b.size()];
}

std::string formatG(double value) {
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%.3g", value);
    return buffer;
}

bool parseHexColor(const std::string& text, std::array<float, 3>* color) {
    if (text.size() != 7 || text[0] != '#') return false;
    for (int c = 0; c < 3; ++c) {
        unsigned value = 0;
        const char* begin = text.data() + 1 + 2 * c;
        auto [end, error] = std::from_chars(begin, begin + 2, value, 16);
        if (error != std::errc() || end != begin + 2) return false;
        (*color)[c] = static_cast<float>(value) / 255.0f;
    }
    return true;
}

// A key of the table being read: where it is (the table's line when the key is absent, so that a
// default that fails a cross-check still points somewhere useful) and its dotted name.
struct Field {
    const toml::node* node = nullptr;
    long line = 0;
    std::string key;
};

class SceneReader {
public:
    explicit SceneReader(std::string file) : m_file(std::move(file)) {}

    Scene read(const toml::table& root) {
        checkKeys(root, "", kRootKeys, std::size(kRootKeys));
        Scene scene;
        readSpecies(root, &scene.species);
        readBox(table(root, "box"), &scene.box);
        readInteraction(table(root, "interaction"), scene.species.size(), &scene.interaction);
        readIntegrator(table(root, "integrator"), &scene.integrator);
        readThermostat(table(root, "thermostat"), &scene.thermostat);
        readInit(table(root, "init"), &scene.init);
        checkFit(scene);
        return scene;
    }

private:
    [[noreturn]] void fail(long line, const std::string& key, const std::string& message) const {
        throw InputError(locatedMessage(m_file, line, key, message));
    }
    void check(const Field& field, bool ok, const std::string& message) const {
        if (!ok) fail(field.line, field.key, message);
    }

    static long lineOf(const toml::node& node) { return static_cast<long>(node.source().begin.line); }

    // The sub-table `name` of the root, or an empty one when absent (every key then defaults).
    const toml::table& table(const toml::table& root, const char* name) {
        static const toml::table kEmpty;
        const toml::node* node = root.get(name);
        if (!node) return kEmpty;
        if (!node->is_table()) fail(lineOf(*node), name, std::string("must be a table: write [") + name + "]");
        const toml::table& result = *node->as_table();
        checkKeys(result, name, tableKeys(name).first, tableKeys(name).second);
        return result;
    }

    static std::pair<const char* const*, size_t> tableKeys(const std::string& name) {
        if (name == "box") return {kBoxKeys, std::size(kBoxKeys)};
        if (name == "interaction") return {kInteractionKeys, std::size(kInteractionKeys)};
        if (name == "integrator") return {kIntegratorKeys, std::size(kIntegratorKeys)};
        if (name == "thermostat") return {kThermostatKeys, std::size(kThermostatKeys)};
        return {kInitKeys, std::size(kInitKeys)};
    }

    void checkKeys(const toml::table& table, const std::string& path, const char* const* allowed, size_t count) const {
        for (auto&& [key, node] : table) {
            std::string name(key.str());
            if (std::find_if(allowed, allowed + count, [&](const char* a) { return name == a; }) != allowed + count) {
                continue;
            }
            std::string message = std::string(path.empty() ? "unknown table '" : "unknown key '") + name + "'";
            for (size_t i = 0; i < count; ++i) {
                if (editDistance(name, allowed[i]) <= 2) {
                    message += std::string(" (did you mean '") + allowed[i] + "'?)";
                    break;
                }
            }
            message += "; allowed: " + joined(allowed, count);
            fail(static_cast<long>(key.source().begin.line), path.empty() ? name : path + "." + name, message);
        }
    }

    static Field field(const toml::table& table, const std::string& path, const char* name) {
        Field f;
        f.node = table.get(name);
        f.line = lineOf(f.node ? *f.node : table);
        f.key = path + "." + name;
        return f;
    }

    // The readers leave *out unchanged (the default) when the key is absent.
    void readNumber(const Field& f, double* out) const {
        if (!f.node) return;
        if (auto integer = f.node->value_exact<int64_t>()) {
            *out = static_cast<double>(*integer);
        } else if (auto real = f.node->value_exact<double>()) {
            check(f, std::isfinite(*real), "must be a finite number");
            *out = *real;
        } else {
            fail(f.line, f.key, "must be a number");
        }
    }

    void readInteger(const Field& f, int64_t* out) const {
        if (!f.node) return;
        auto integer = f.node->value_exact<int64_t>();
        check(f, integer.has_value(), "must be an integer");
        *out = *integer;
    }

    void readBool(const Field& f, bool* out) const {
        if (!f.node) return;
        auto value = f.node->value_exact<bool>();
        check(f, value.has_value(), "must be true or false");
        *out = *value;
    }

    void readString(const Field& f, std::string* out) const {
        if (!f.node) return;
        auto value = f.node->value_exact<std::string>();
        check(f, value.has_value(), "must be a string");
        *out = *value;
    }

    template <class Enum>
    void readChoice(const Field& f, const Vocabulary<Enum>& table, Enum* out) const {
        std::string text;
        if (!f.node) return;
        readString(f, &text);
        check(f, table.parse(text, out), table.unknown(text));
    }

    void readVec3(const Field& f, std::array<double, 3>* out) const {
        if (!f.node) return;
        const toml::array* array = f.node->as_array();
        check(f, array && array->size() == 3, "must be an array of 3 numbers");
        for (size_t i = 0; i < 3; ++i) {
            const toml::node& element = *array->get(i);
            readNumber(Field{&element, lineOf(element), f.key + "[" + std::to_string(i) + "]"}, &(*out)[i]);
        }
    }

    void readBox(const toml::table& t, BoxDef* box) const {
        Field size = field(t, "box", "size");
        readVec3(size, &box->size);
        check(size, std::all_of(box->size.begin(), box->size.end(), [](double l) { return l > 0; }),
              "must be 3 positive numbers");
        Field restitution = field(t, "box", "wall_restitution");
        readNumber(restitution, &box->wallRestitution);
        checkUnitInterval(restitution, box->wallRestitution);
    }

    void checkUnitInterval(const Field& f, double value) const {
        check(f, value >= 0 && value <= 1, "must be in [0, 1]");
    }

    void readSpecies(const toml::table& root, std::vector<SpeciesDef>* species) {
        const toml::node* node = root.get("species");
        if (!node) fail(0, "species", "no [[species]] given; at least one is required");
        const toml::array* array = node->as_array();
        if (!array) fail(lineOf(*node), "species", "must be an array of tables: write [[species]]");
        if (array->empty()) fail(lineOf(*node), "species", "at least one [[species]] is required");
        m_speciesLine = lineOf(*array->get(0));
        for (size_t i = 0; i < array->size(); ++i) {
            const toml::node& element = *array->get(i);
            std::string path = "species[" + std::to_string(i) + "]";
            if (!element.is_table()) fail(lineOf(element), path, "must be a table");
            species->push_back(readOneSpecies(*element.as_table(), path, i));
        }
        for (size_t i = 0; i < species->size(); ++i) {
            for (size_t j = 0; j < i; ++j) {
                if ((*species)[i].name == (*species)[j].name) {
                    Field name = field(*array->get(i)->as_table(), "species[" + std::to_string(i) + "]", "name");
                    fail(name.line, name.key, "duplicate species name '" + (*species)[i].name + "' (also species[" +
                                                  std::to_string(j) + "])");
                }
            }
        }
        int64_t total = 0;
        for (const SpeciesDef& s : *species) total += s.count;
        if (total == 0) fail(m_speciesLine, "species", "total particle count is 0; give some species a count > 0");
    }

    SpeciesDef readOneSpecies(const toml::table& t, const std::string& path, size_t index) {
        checkKeys(t, path, kSpeciesKeys, std::size(kSpeciesKeys));
        SpeciesDef s;
        s.name = index < 26 ? std::string(1, static_cast<char>('A' + index)) : "S" + std::to_string(index);
        parseHexColor(kPalette[index % std::size(kPalette)], &s.color);

        Field name = field(t, path, "name");
        readString(name, &s.name);
        check(name, !s.name.empty(), "must not be empty");

        Field count = field(t, path, "count");
        check(count, count.node != nullptr, "missing required key 'count'");
        readInteger(count, &s.count);
        check(count, s.count >= 0, "must be >= 0");

        Field mass = field(t, path, "mass");
        readNumber(mass, &s.mass);
        check(mass, s.mass > 0, "must be > 0");
        Field radius = field(t, path, "radius");
        readNumber(radius, &s.radius);
        check(radius, s.radius > 0, "must be > 0");
        m_radiusLines.push_back(radius.line);
        Field sigma = field(t, path, "sigma");
        readNumber(sigma, &s.sigma);
        check(sigma, s.sigma > 0, "must be > 0");
        Field epsilon = field(t, path, "epsilon");
        readNumber(epsilon, &s.epsilon);
        check(epsilon, s.epsilon >= 0, "must be >= 0");

        Field color = field(t, path, "color");
        if (color.node) {
            std::string text;
            readString(color, &text);
            check(color, parseHexColor(text, &s.color), "must be \"#rrggbb\" (hex digits), not '" + text + "'");
        }
        return s;
    }

    void readInteraction(const toml::table& t, size_t speciesCount, InteractionDef* in) const {
        readMixing(field(t, "interaction", "mixing"), speciesCount, &in->mixing);

        Field cutoff = field(t, "interaction", "cutoff");
        readNumber(cutoff, &in->cutoff);
        check(cutoff, in->cutoff >= 0, "must be >= 0 (0: all pairs)");
        readChoice(field(t, "interaction", "shift"), shiftTable(), &in->shift);
        Field restitution = field(t, "interaction", "restitution");
        readNumber(restitution, &in->restitution);
        checkUnitInterval(restitution, in->restitution);
        readVec3(field(t, "interaction", "gravity"), &in->gravity);

        Field slow = field(t, "interaction", "elastic_below_speed");
        readNumber(slow, &in->elasticBelowSpeed);
        check(slow, in->elasticBelowSpeed >= 0, "must be >= 0");

        Field rounds = field(t, "interaction", "max_collision_rounds");
        int64_t roundCount = in->maxCollisionRounds;
        readInteger(rounds, &roundCount);
        check(rounds, roundCount >= 1, "must be >= 1");
        check(rounds, roundCount <= INT_MAX, "must be <= " + std::to_string(INT_MAX));
        in->maxCollisionRounds = static_cast<int>(roundCount);
    }

    // x_ij: S rows of S non-negative numbers, symmetric; an empty array means 1 for every pair.
    void readMixing(const Field& f, size_t s, std::vector<std::vector<double>>* mixing) const {
        if (!f.node) return;
        const std::string shape = "must be a " + std::to_string(s) + "x" + std::to_string(s) +
                                  " array of arrays (one row per species)";
        const toml::array* rows = f.node->as_array();
        check(f, rows != nullptr, shape);
        if (rows->empty()) return;
        check(f, rows->size() == s, shape + ", found " + std::to_string(rows->size()) + " rows");
        mixing->assign(s, std::vector<double>(s, 0.0));
        for (size_t i = 0; i < s; ++i) {
            const toml::node& rowNode = *rows->get(i);
            Field row{&rowNode, lineOf(rowNode), f.key + "[" + std::to_string(i) + "]"};
            const toml::array* values = rowNode.as_array();
            check(row, values && values->size() == s, shape);
            for (size_t j = 0; j < s; ++j) {
                const toml::node& valueNode = *values->get(j);
                Field value{&valueNode, lineOf(valueNode), row.key + "[" + std::to_string(j) + "]"};
                readNumber(value, &(*mixing)[i][j]);
                check(value, (*mixing)[i][j] >= 0, "must be >= 0");
                if (j < i) {
                    check(value, (*mixing)[i][j] == (*mixing)[j][i],
                          "must equal " + f.key + "[" + std::to_string(j) + "][" + std::to_string(i) +
                              "]: the mixing matrix is symmetric");
                }
            }
        }
    }

    void readIntegrator(const toml::table& t, IntegratorDef* in) const {
        readChoice(field(t, "integrator", "method"), methodTable(), &in->method);

        Field dt = field(t, "integrator", "dt");
        readNumber(dt, &in->dt);
        check(dt, in->dt > 0, "must be > 0");
        readChoice(field(t, "integrator", "precision"), precisionTable(), &in->precision);
        Field adaptive = field(t, "integrator", "adaptive");
        readBool(adaptive, &in->adaptive);
        check(adaptive, !in->adaptive || in->method == Method::Dp5,
              std::string("needs method = \"dp5\" (the only method with an error estimate), not \"") +
                  methodName(in->method) + "\"");
        Field tolerance = field(t, "integrator", "tolerance");
        readNumber(tolerance, &in->tolerance);
        check(tolerance, in->tolerance > 0, "must be > 0");
    }

    void readThermostat(const toml::table& t, ThermostatDef* th) const {
        readChoice(field(t, "thermostat", "kind"), thermostatTable(), &th->kind);
        Field temperature = field(t, "thermostat", "temperature");
        readNumber(temperature, &th->temperature);
        check(temperature, th->temperature >= 0, "must be >= 0");
        Field tau = field(t, "thermostat", "tau");
        readNumber(tau, &th->tau);
        check(tau, th->tau > 0, "must be > 0");
    }

    void readInit(const toml::table& t, InitDef* init) const {
        Field temperature = field(t, "init", "temperature");
        readNumber(temperature, &init->temperature);
        check(temperature, init->temperature >= 0, "must be >= 0");
        Field seed = field(t, "init", "seed");
        int64_t seedValue = static_cast<int64_t>(init->seed);
        readInteger(seed, &seedValue);
        check(seed, seedValue >= 0, "must be >= 0");
        init->seed = static_cast<uint64_t>(seedValue);
        readChoice(field(t, "init", "placement"), placementTable(), &init->placement);
        readString(field(t, "init", "particles"), &init->particlesFile);
    }

    // Hard cores must fit: each one inside the box, and all of them together well below close packing.
    void checkFit(const Scene& scene) const {
        const auto& size = scene.box.size;
        double smallestEdge = *std::min_element(size.begin(), size.end());
        double coreVolume = 0;
        for (size_t i = 0; i < scene.species.size(); ++i) {
            const SpeciesDef& s = scene.species[i];
            if (2 * s.radius > smallestEdge) {
                fail(m_radiusLines[i], "species[" + std::to_string(i) + "].radius",
                     "diameter " + formatG(2 * s.radius) + " exceeds the smallest box edge " + formatG(smallestEdge));
            }
            coreVolume += static_cast<double>(s.count) * 4.0 / 3.0 * kPi * s.radius * s.radius * s.radius;
        }
        double fraction = coreVolume / (size[0] * size[1] * size[2]);
        if (fraction > kMaxPackingFraction) {
            fail(m_speciesLine, "species",
                 "more particles than fit: hard-core packing fraction " + formatG(fraction) + " exceeds the limit " +
                     formatG(kMaxPackingFraction) + "; enlarge box.size or lower the counts");
        }
    }

    std::string m_file;
    long m_speciesLine = 0;          // line of the first [[species]], for errors about all species together
    std::vector<long> m_radiusLines;  // per species, for the cross-check against the box
};

// ---- writing ------------------------------------------------------------------------------------

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

std::string readFile(const std::string& path) {
    std::error_code ec;
    if (fs::is_directory(path, ec)) throw InputError("cannot read '" + path + "': is a directory");
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError("cannot read '" + path + "': " + std::strerror(errno));
    std::ostringstream text;
    text << in.rdbuf();
    if (in.bad()) throw InputError("cannot read '" + path + "': " + std::strerror(errno));
    return text.str();
}

}  // namespace

Scene parseScene(const std::string& text, const std::string& sourceName) {
    toml::table root;
    try {
        root = toml::parse(text, sourceName);
    } catch (const toml::parse_error& error) {
        throw InputError(locatedMessage(sourceName, static_cast<long>(error.source().begin.line), "",
                                        std::string(error.description())));
    }
    return SceneReader(sourceName).read(root);
}

Scene loadScene(const std::string& path) {
    Scene scene = parseScene(readFile(path), path);
    scene.sourcePath = path;
    fs::path particles(scene.init.particlesFile);
    if (!particles.empty() && particles.is_relative()) {
        scene.init.particlesFile = (fs::path(path).parent_path() / particles).lexically_normal().string();
    }
    return scene;
}

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
        << "max_collision_rounds = " << in.maxCollisionRounds << "\n";

    const IntegratorDef& integrator = scene.integrator;
    out << "\n[integrator]\n"
        << "method = " << quoted(methodName(integrator.method)) << "\n"
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
