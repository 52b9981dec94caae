// Reading scene files: TOML syntax, the allowed tables and keys, the type of every value and the
// names of every choice. What the values must satisfy is scene_validation.cpp's; this file records
// where each key was written so that those errors name the line too.
#include "scene_io.h"

#include <toml++/toml.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <climits>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <utility>

#include "errors.h"
#include "scene_validation.h"
#include "suggest.h"

namespace corebox {
namespace {

namespace fs = std::filesystem;

const char* const kRootKeys[] = {"box", "species", "interaction", "integrator", "thermostat", "init", "devices"};
const char* const kBoxKeys[] = {"size", "wall_restitution"};
const char* const kSpeciesKeys[] = {"name", "count", "mass", "radius", "sigma", "epsilon", "color", "acceleration"};
const char* const kInteractionKeys[] = {"mixing",
                                        "cutoff",
                                        "shift",
                                        "restitution",
                                        "gravity",
                                        "elastic_below_speed",
                                        "max_collision_rounds",
                                        "contact_sweeps",
                                        "contact_listings",
                                        "forces",
                                        "skin"};
const char* const kIntegratorKeys[] = {"method", "dt", "precision", "adaptive", "tolerance"};
const char* const kThermostatKeys[] = {"kind", "temperature", "tau"};
const char* const kInitKeys[] = {"temperature", "seed", "placement", "particles"};
const char* const kDevicesKeys[] = {"gpus", "exchange"};

// Colours for species that give none, by position: distinct under the renderer's shading.
const char* const kPalette[] = {"#cc4d33", "#3373cc", "#4dad4d", "#d9a626", "#8c4dbf", "#33b3b3"};

std::string joined(const char* const* names, size_t count) {
    std::string out;
    for (size_t i = 0; i < count; ++i) out += (i ? ", " : "") + std::string(names[i]);
    return out;
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

// Reads a scene and notes in `where` the line of every key it meets (or would have met).
class SceneReader {
public:
    explicit SceneReader(SceneLocations& where) : m_where(where) {}

    Scene read(const toml::table& root) {
        checkKeys(root, "", kRootKeys, std::size(kRootKeys));
        Scene scene;
        readSpecies(root, &scene.species);
        readBox(table(root, "box"), &scene.box);
        readInteraction(table(root, "interaction"), scene.species.size(), &scene.interaction);
        readIntegrator(table(root, "integrator"), &scene.integrator);
        readThermostat(table(root, "thermostat"), &scene.thermostat);
        readInit(table(root, "init"), &scene.init);
        readDevices(table(root, "devices"), &scene.devices);
        return scene;
    }

private:
    [[noreturn]] void fail(long line, const std::string& key, const std::string& message) const {
        throw InputError(locatedMessage(m_where.file(), line, key, message));
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
        if (name == "devices") return {kDevicesKeys, std::size(kDevicesKeys)};
        return {kInitKeys, std::size(kInitKeys)};
    }

    void checkKeys(const toml::table& table, const std::string& path, const char* const* allowed, size_t count) const {
        for (auto&& [key, node] : table) {
            std::string name(key.str());
            if (std::find_if(allowed, allowed + count, [&](const char* a) { return name == a; }) != allowed + count) {
                continue;
            }
            const std::string message = std::string(path.empty() ? "unknown table '" : "unknown key '") + name + "'" +
                                        didYouMean(name, allowed, count) + "; allowed: " + joined(allowed, count);
            fail(static_cast<long>(key.source().begin.line), path.empty() ? name : path + "." + name, message);
        }
    }

    Field field(const toml::table& table, const std::string& path, const char* name) const {
        Field f;
        f.node = table.get(name);
        f.line = lineOf(f.node ? *f.node : table);
        f.key = path + "." + name;
        m_where.set(f.key, f.line);
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

    // A cap held as an int: above INT_MAX is refused here; below `floor` it is clamped to `floor`, which
    // validation refuses alike (clamping keeps the narrowing well defined).
    void readIntCap(const Field& f, int floor, int* out) const {
        int64_t value = *out;
        readInteger(f, &value);
        check(f, value <= INT_MAX, "must be <= " + std::to_string(INT_MAX));
        *out = static_cast<int>(std::max<int64_t>(value, floor));
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
        readVec3(field(t, "box", "size"), &box->size);
        readNumber(field(t, "box", "wall_restitution"), &box->wallRestitution);
    }

    void readSpecies(const toml::table& root, std::vector<SpeciesDef>* species) {
        const toml::node* node = root.get("species");
        if (!node) fail(0, "species", "no [[species]] given; at least one is required");
        const toml::array* array = node->as_array();
        if (!array) fail(lineOf(*node), "species", "must be an array of tables: write [[species]]");
        if (array->empty()) fail(lineOf(*node), "species", "at least one [[species]] is required");
        m_where.set("species", lineOf(*array->get(0)));  // for errors about all species together
        for (size_t i = 0; i < array->size(); ++i) {
            const toml::node& element = *array->get(i);
            std::string path = "species[" + std::to_string(i) + "]";
            if (!element.is_table()) fail(lineOf(element), path, "must be a table");
            species->push_back(readOneSpecies(*element.as_table(), path, i));
        }
    }

    SpeciesDef readOneSpecies(const toml::table& t, const std::string& path, size_t index) {
        checkKeys(t, path, kSpeciesKeys, std::size(kSpeciesKeys));
        SpeciesDef s;
        s.name = index < 26 ? std::string(1, static_cast<char>('A' + index)) : "S" + std::to_string(index);
        parseHexColor(kPalette[index % std::size(kPalette)], &s.color);

        readString(field(t, path, "name"), &s.name);
        Field count = field(t, path, "count");
        check(count, count.node != nullptr, "missing required key 'count'");
        readInteger(count, &s.count);
        readNumber(field(t, path, "mass"), &s.mass);
        readNumber(field(t, path, "radius"), &s.radius);
        readNumber(field(t, path, "sigma"), &s.sigma);
        readNumber(field(t, path, "epsilon"), &s.epsilon);
        readVec3(field(t, path, "acceleration"), &s.acceleration);

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

        readNumber(field(t, "interaction", "cutoff"), &in->cutoff);
        readChoice(field(t, "interaction", "shift"), shiftTable(), &in->shift);
        readNumber(field(t, "interaction", "restitution"), &in->restitution);
        readVec3(field(t, "interaction", "gravity"), &in->gravity);
        readNumber(field(t, "interaction", "elastic_below_speed"), &in->elasticBelowSpeed);
        readChoice(field(t, "interaction", "forces"), forceModelTable(), &in->forces);
        readNumber(field(t, "interaction", "skin"), &in->skin);

        readIntCap(field(t, "interaction", "max_collision_rounds"), 0, &in->maxCollisionRounds);  // >= 1 valid
        readIntCap(field(t, "interaction", "contact_sweeps"), -1, &in->contactSweeps);            // >= 0 valid
        readIntCap(field(t, "interaction", "contact_listings"), -1, &in->contactListings);        // 0 to 32 valid
    }

    // x_ij: S rows of S numbers (validation checks them); an empty array means 1 for every pair.
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
                m_where.set(value.key, value.line);
                readNumber(value, &(*mixing)[i][j]);
            }
        }
    }

    void readIntegrator(const toml::table& t, IntegratorDef* in) const {
        const Field method = field(t, "integrator", "method");
        if (method.node) {
            std::string text;
            readString(method, &text);
            in->automatic = text == "auto";
            check(method, in->automatic || methodTable().parse(text, &in->method), methodTable().unknown(text) + ", or auto");
        }

        readNumber(field(t, "integrator", "dt"), &in->dt);
        readChoice(field(t, "integrator", "precision"), precisionTable(), &in->precision);
        readBool(field(t, "integrator", "adaptive"), &in->adaptive);
        readNumber(field(t, "integrator", "tolerance"), &in->tolerance);
    }

    void readThermostat(const toml::table& t, ThermostatDef* th) const {
        readChoice(field(t, "thermostat", "kind"), thermostatTable(), &th->kind);
        readNumber(field(t, "thermostat", "temperature"), &th->temperature);
        readNumber(field(t, "thermostat", "tau"), &th->tau);
    }

    void readInit(const toml::table& t, InitDef* init) const {
        readNumber(field(t, "init", "temperature"), &init->temperature);
        Field seed = field(t, "init", "seed");
        int64_t seedValue = static_cast<int64_t>(init->seed);
        readInteger(seed, &seedValue);
        check(seed, seedValue >= 0, "must be >= 0");  // here, not in validation: the seed is unsigned
        init->seed = static_cast<uint64_t>(seedValue);
        readChoice(field(t, "init", "placement"), placementTable(), &init->placement);
        readString(field(t, "init", "particles"), &init->particlesFile);
    }

    void readDevices(const toml::table& t, DevicesDef* devices) const {
        const Field gpus = field(t, "devices", "gpus");
        if (gpus.node) {
            if (auto text = gpus.node->value_exact<std::string>()) {
                check(gpus, *text == "auto", "must be a GPU count (1, 2, ...) or \"auto\"");
                devices->gpus = 0;
            } else {
                int64_t count = 0;
                readInteger(gpus, &count);
                check(gpus, count >= 1 && count <= 1024, "must be a GPU count from 1 up (or \"auto\")");
                devices->gpus = int(count);
            }
        }
        readChoice(field(t, "devices", "exchange"), exchangeTable(), &devices->exchange);
    }

    SceneLocations& m_where;
};

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
    SceneLocations where(sourceName);
    Scene scene = SceneReader(where).read(root);
    validateScene(scene, where);
    return scene;
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

}  // namespace corebox
