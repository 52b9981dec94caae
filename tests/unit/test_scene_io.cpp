// Scene files: the presets parse and are sensible, sceneToToml round-trips every field, and every
// kind of bad input is refused with a message naming the file, the line and the key.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "bench_scenes.h"  // pileScene: the scene of `corebox bench pile`
#include "errors.h"
#include "scene_io.h"

using namespace corebox;

namespace {

constexpr double kPi = 3.14159265358979323846;

const std::string kOneSpecies = "[[species]]\ncount = 3\n";

const char* const kPresets[] = {"hard_spheres", "argon_gas", "binary_mixture", "polydisperse", "granular_cooling",
                                "bouncing"};

std::string presetPath(const std::string& name) { return std::string(COREBOX_SOURCE_DIR) + "/assets/" + name + ".toml"; }

void expectSameScene(const Scene& a, const Scene& b) {
    EXPECT_EQ(a.box.size, b.box.size);
    EXPECT_EQ(a.box.wallRestitution, b.box.wallRestitution);
    ASSERT_EQ(a.species.size(), b.species.size());
    for (size_t i = 0; i < a.species.size(); ++i) {
        SCOPED_TRACE("species " + std::to_string(i));
        const SpeciesDef& s = a.species[i];
        const SpeciesDef& t = b.species[i];
        EXPECT_EQ(s.name, t.name);
        EXPECT_EQ(s.count, t.count);
        EXPECT_EQ(s.mass, t.mass);
        EXPECT_EQ(s.radius, t.radius);
        EXPECT_EQ(s.sigma, t.sigma);
        EXPECT_EQ(s.epsilon, t.epsilon);
        EXPECT_EQ(s.color, t.color);
        EXPECT_EQ(s.acceleration, t.acceleration);
    }
    EXPECT_EQ(a.interaction.mixing, b.interaction.mixing);
    EXPECT_EQ(a.interaction.cutoff, b.interaction.cutoff);
    EXPECT_EQ(a.interaction.shift, b.interaction.shift);
    EXPECT_EQ(a.interaction.restitution, b.interaction.restitution);
    EXPECT_EQ(a.interaction.gravity, b.interaction.gravity);
    EXPECT_EQ(a.interaction.elasticBelowSpeed, b.interaction.elasticBelowSpeed);
    EXPECT_EQ(a.interaction.maxCollisionRounds, b.interaction.maxCollisionRounds);
    EXPECT_EQ(a.interaction.contactSweeps, b.interaction.contactSweeps);
    EXPECT_EQ(a.interaction.contactListings, b.interaction.contactListings);
    EXPECT_EQ(a.interaction.forces, b.interaction.forces);
    EXPECT_EQ(a.interaction.skin, b.interaction.skin);
    EXPECT_EQ(a.integrator.method, b.integrator.method);
    EXPECT_EQ(a.integrator.dt, b.integrator.dt);
    EXPECT_EQ(a.integrator.precision, b.integrator.precision);
    EXPECT_EQ(a.integrator.adaptive, b.integrator.adaptive);
    EXPECT_EQ(a.integrator.tolerance, b.integrator.tolerance);
    EXPECT_EQ(a.thermostat.kind, b.thermostat.kind);
    EXPECT_EQ(a.thermostat.temperature, b.thermostat.temperature);
    EXPECT_EQ(a.thermostat.tau, b.thermostat.tau);
    EXPECT_EQ(a.init.temperature, b.init.temperature);
    EXPECT_EQ(a.init.seed, b.init.seed);
    EXPECT_EQ(a.init.placement, b.init.placement);
    EXPECT_EQ(a.init.particlesFile, b.init.particlesFile);
    EXPECT_EQ(a.devices.gpus, b.devices.gpus);
    EXPECT_EQ(a.devices.exchange, b.devices.exchange);
}

// A fresh directory under the test temp dir, so tests can write scene and particle files.
std::filesystem::path scratchDir(const std::string& name) {
    std::filesystem::path dir = std::filesystem::path(testing::TempDir()) / ("corebox_scene_io_" + name);
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    return dir;
}

void writeText(const std::filesystem::path& path, const std::string& text) {
    std::ofstream out(path);
    out << text;
}

}  // namespace

// ---- presets --------------------------------------------------------------------------------------

TEST(SceneIoPresets, EveryPresetLoadsAndIsCheapAndDilute) {
    for (const char* name : kPresets) {
        SCOPED_TRACE(name);
        Scene scene = loadScene(presetPath(name));
        EXPECT_EQ(scene.sourcePath, presetPath(name));
        // Fast on a 2-core CPU with an O(N^2) force pass.
        EXPECT_GE(scene.particleCount(), 200);
        EXPECT_LE(scene.particleCount(), 1000);
        EXPECT_TRUE(scene.integrator.method == Method::Rk4 || scene.integrator.method == Method::Verlet);
        EXPECT_GE(scene.integrator.dt, 1e-3);
        EXPECT_LE(scene.integrator.dt, 5e-3);
        // Dilute: packing fraction of the effective diameter (the LJ sigma or the hard core).
        double volume = 0;
        for (const SpeciesDef& s : scene.species) {
            double radius = std::max(s.radius, s.sigma / 2);
            volume += double(s.count) * 4.0 / 3.0 * kPi * radius * radius * radius;
        }
        double fraction = volume / (scene.box.size[0] * scene.box.size[1] * scene.box.size[2]);
        EXPECT_GE(fraction, 0.05);
        EXPECT_LE(fraction, 0.2);
    }
}

TEST(SceneIoPresets, PresetsSetTheirDefiningPhysics) {
    Scene hard = loadScene(presetPath("hard_spheres"));
    EXPECT_EQ(hard.species.at(0).epsilon, 0.0);
    EXPECT_EQ(hard.interaction.restitution, 1.0);
    EXPECT_EQ(hard.box.wallRestitution, 1.0);
    EXPECT_EQ(hard.thermostat.kind, ThermostatKind::None);

    Scene argon = loadScene(presetPath("argon_gas"));
    ASSERT_EQ(argon.species.size(), 1u);
    EXPECT_GT(argon.species[0].epsilon, 0.0);
    EXPECT_EQ(argon.interaction.cutoff, 2.5);
    EXPECT_EQ(argon.interaction.shift, CutoffShift::Force);
    EXPECT_EQ(argon.thermostat.kind, ThermostatKind::Bussi);
    EXPECT_EQ(argon.thermostat.temperature, 1.5);

    Scene binary = loadScene(presetPath("binary_mixture"));
    ASSERT_EQ(binary.species.size(), 2u);
    EXPECT_EQ(binary.species[0].name, "A");
    EXPECT_EQ(binary.species[1].name, "B");
    EXPECT_LT(binary.mixing(0, 1), binary.mixing(0, 0));
    EXPECT_EQ(binary.mixing(0, 1), 0.3);
    EXPECT_EQ(binary.thermostat.temperature, 0.8);

    Scene poly = loadScene(presetPath("polydisperse"));
    EXPECT_GE(poly.species.size(), 3u);
    EXPECT_LE(poly.species.size(), 4u);
    EXPECT_NE(poly.species[0].radius, poly.species[1].radius);
    EXPECT_NE(poly.species[0].mass, poly.species[1].mass);

    Scene granular = loadScene(presetPath("granular_cooling"));
    EXPECT_EQ(granular.interaction.restitution, 0.9);
    EXPECT_EQ(granular.box.wallRestitution, 0.9);
    EXPECT_EQ(granular.thermostat.kind, ThermostatKind::None);
    EXPECT_EQ(granular.species.at(0).epsilon, 0.0);

    Scene bouncing = loadScene(presetPath("bouncing"));
    EXPECT_LT(bouncing.interaction.gravity[2], 0.0);
    EXPECT_EQ(bouncing.box.wallRestitution, 0.8);
    EXPECT_EQ(bouncing.interaction.restitution, 0.9);
    EXPECT_EQ(bouncing.species.at(0).epsilon, 0.0);
    EXPECT_EQ(bouncing.thermostat.kind, ThermostatKind::None);
}

// assets/dense_hard_spheres.toml (4,000 spheres at packing fraction 0.45: outside kPresets, which are
// dilute) is the elastic hard-sphere fluid of the dense tests and `corebox bench hardspheres`.
TEST(SceneIoPresets, DenseHardSpheresIsTheElasticFluidAtPhi045) {
    const Scene dense = loadScene(presetPath("dense_hard_spheres"));
    ASSERT_EQ(dense.species.size(), 1u);
    const SpeciesDef& s = dense.species[0];
    EXPECT_EQ(s.epsilon, 0.0);
    EXPECT_EQ(s.radius, 0.5);
    EXPECT_EQ(dense.interaction.restitution, 1.0);
    EXPECT_EQ(dense.box.wallRestitution, 1.0);
    EXPECT_EQ(dense.interaction.gravity, (std::array<double, 3>{0, 0, 0}));
    EXPECT_EQ(dense.thermostat.kind, ThermostatKind::None);
    const double volume = dense.box.size[0] * dense.box.size[1] * dense.box.size[2];
    EXPECT_NEAR(double(s.count) * 3.14159265358979323846 / 6.0 / volume, 0.45, 5e-4);
    expectSameScene(parseScene(sceneToToml(dense), "round_trip.toml"), dense);
}

// assets/pile.toml (10^4 balls, not cheap: outside kPresets) is the scene the pile benchmark builds in
// code at that N, field for field, so the preset and the benchmark measure one scene.
TEST(SceneIoPresets, PileIsTheBenchmarkScene) {
    const Scene pile = loadScene(presetPath("pile"));
    expectSameScene(pile, pileScene(kPile.presetCount, Precision::Fp64));
    EXPECT_EQ(pile.particleCount(), 10000);
    EXPECT_EQ(pile.integrator.dt, 1.0 / 240.0);  // the decimal in the file is 1/240 to the last bit
    EXPECT_EQ(pile.box.size[2], 60.0);           // gravity along the tall axis
    EXPECT_LT(pile.interaction.gravity[2], 0.0);
    EXPECT_EQ(pile.species.at(0).epsilon, 0.0);
    EXPECT_EQ(pile.thermostat.kind, ThermostatKind::None);
    expectSameScene(parseScene(sceneToToml(pile), "round_trip.toml"), pile);
}

// ---- round trip -----------------------------------------------------------------------------------

TEST(SceneIoRoundTrip, EveryPresetSurvivesSceneToToml) {
    for (const char* name : kPresets) {
        SCOPED_TRACE(name);
        Scene scene = loadScene(presetPath(name));
        expectSameScene(parseScene(sceneToToml(scene), "round_trip.toml"), scene);
    }
}

TEST(SceneIoRoundTrip, EveryNonDefaultFieldSurvives) {
    Scene scene;
    scene.box.size = {7.25, 8.0, 1e3};
    scene.box.wallRestitution = 0.3;
    SpeciesDef a;
    a.name = "a \"quoted\" \\ name\twith tab, ünïcode";
    a.count = 7;
    a.mass = 0.1;
    a.radius = 0.3;
    a.sigma = 0.7;
    a.epsilon = 0;
    a.color = {1.0f, 128 / 255.0f, 0.0f};
    SpeciesDef b = a;
    b.name = "B";
    b.count = 0;
    b.mass = 1.0 / 3.0;  // needs all 17 digits
    b.acceleration = {0.25, 9.81, -1.0 / 3.0};  // a species' own field, added to gravity
    scene.species = {a, b};
    scene.interaction.mixing = {{1.0, 0.1}, {0.1, 2.0}};
    scene.interaction.cutoff = 3.0;
    scene.interaction.shift = CutoffShift::Energy;
    scene.interaction.restitution = 0.0;
    scene.interaction.gravity = {0.5, -1e-12, -9.81};
    scene.interaction.elasticBelowSpeed = 0;
    scene.interaction.maxCollisionRounds = 1;
    scene.interaction.contactSweeps = 24;
    scene.interaction.contactListings = 3;
    scene.interaction.forces = ForceModel::NeighbourList;
    scene.interaction.skin = 0.45;
    scene.integrator.method = Method::Dp5;
    scene.integrator.dt = 1e-7;
    scene.integrator.precision = Precision::Fp32;
    scene.integrator.adaptive = true;
    scene.integrator.tolerance = 1e-12;
    scene.thermostat.kind = ThermostatKind::Rescale;
    scene.thermostat.temperature = 0;
    scene.thermostat.tau = 2.5;
    scene.init.temperature = 1e-300;
    scene.init.seed = 9223372036854775807ull;
    scene.init.placement = Placement::Random;
    scene.init.particlesFile = "dir with space/\"start\".csv";
    scene.devices.gpus = 3;
    scene.devices.exchange = Exchange::Nccl;

    expectSameScene(parseScene(sceneToToml(scene), "round_trip.toml"), scene);
    for (Method method : {Method::Euler, Method::Rk2, Method::Hairer10, Method::Verlet}) {
        scene.integrator.method = method;
        scene.integrator.adaptive = false;
        EXPECT_EQ(parseScene(sceneToToml(scene), "round_trip.toml").integrator.method, method);
    }
}

// ---- defaults and accepted forms ---------------------------------------------------------------------

TEST(SceneIoParse, MissingKeysTakeTheStructDefaults) {
    Scene scene = parseScene("[[species]]\ncount = 3\n[[species]]\ncount = 4\n", "min.toml");
    Scene defaults;
    SpeciesDef species;
    ASSERT_EQ(scene.species.size(), 2u);
    EXPECT_EQ(scene.species[0].name, "A");  // named by position so unnamed species do not collide
    EXPECT_EQ(scene.species[1].name, "B");
    EXPECT_NE(scene.species[0].color, scene.species[1].color);
    EXPECT_EQ(scene.species[1].count, 4);
    EXPECT_EQ(scene.species[1].mass, species.mass);
    EXPECT_EQ(scene.species[1].radius, species.radius);
    EXPECT_EQ(scene.species[1].sigma, species.sigma);
    EXPECT_EQ(scene.species[1].epsilon, species.epsilon);
    EXPECT_EQ(scene.box.size, defaults.box.size);
    EXPECT_TRUE(scene.interaction.mixing.empty());
    EXPECT_EQ(scene.interaction.shift, defaults.interaction.shift);
    EXPECT_EQ(scene.interaction.maxCollisionRounds, defaults.interaction.maxCollisionRounds);
    EXPECT_EQ(scene.interaction.contactSweeps, defaults.interaction.contactSweeps);
    EXPECT_EQ(scene.interaction.contactListings, defaults.interaction.contactListings);
    EXPECT_EQ(scene.integrator.method, defaults.integrator.method);
    EXPECT_EQ(scene.integrator.dt, defaults.integrator.dt);
    EXPECT_EQ(scene.thermostat.kind, defaults.thermostat.kind);
    EXPECT_EQ(scene.init.seed, defaults.init.seed);
    EXPECT_EQ(scene.init.placement, defaults.init.placement);
    EXPECT_EQ(scene.sourcePath, "");
}

TEST(SceneIoParse, DevicesTakeACountOrAuto) {
    EXPECT_EQ(parseScene(kOneSpecies + "[devices]\ngpus = 2\nexchange = \"da\"\n", "d.toml").devices.gpus, 2);
    EXPECT_EQ(parseScene(kOneSpecies + "[devices]\ngpus = 2\nexchange = \"da\"\n", "d.toml").devices.exchange, Exchange::Da);
    EXPECT_EQ(parseScene(kOneSpecies + "[devices]\ngpus = \"auto\"\n", "d.toml").devices.gpus, 0);
    EXPECT_EQ(parseScene(kOneSpecies, "d.toml").devices.exchange, Exchange::Auto);
}

TEST(SceneIoParse, ForcesAndSkin) {
    EXPECT_EQ(parseScene(kOneSpecies, "f.toml").interaction.forces, ForceModel::Auto);
    EXPECT_EQ(parseScene(kOneSpecies, "f.toml").interaction.skin, 0.3);
    for (ForceModel m : {ForceModel::Auto, ForceModel::AllPairs}) {
        const std::string text = kOneSpecies + "[interaction]\nforces = \"" + forceModelName(m) + "\"\n";
        EXPECT_EQ(parseScene(text, "f.toml").interaction.forces, m);
    }
    const Scene lists = parseScene(kOneSpecies + "[interaction]\ncutoff = 2.5\nforces = \"neighbour_list\"\nskin = 0.5\n", "f.toml");
    EXPECT_EQ(lists.interaction.forces, ForceModel::NeighbourList);
    EXPECT_EQ(lists.interaction.skin, 0.5);
    expectSameScene(parseScene(sceneToToml(lists), "round_trip.toml"), lists);
    try {
        parseScene(kOneSpecies + "[interaction]\nforces = \"none\"\n", "f.toml");
        FAIL() << "'none' is not a choice of forces";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("all_pairs"), std::string::npos) << e.what();
    }
}

TEST(SceneIoParse, IntegersAreAcceptedForFloats) {
    Scene scene = parseScene("[box]\nsize = [10, 12, 14]\nwall_restitution = 1\n"
                             "[[species]]\ncount = 5\nmass = 2\n"
                             "[interaction]\nmixing = [[1]]\ngravity = [0, 0, -1]\n",
                             "ints.toml");
    EXPECT_EQ(scene.box.size, (std::array<double, 3>{10, 12, 14}));
    EXPECT_EQ(scene.species[0].mass, 2.0);
    EXPECT_EQ(scene.interaction.mixing, (std::vector<std::vector<double>>{{1.0}}));
    EXPECT_EQ(scene.interaction.gravity[2], -1.0);
}

TEST(SceneIoParse, ColourIsHexOver255) {
    Scene scene = parseScene("[[species]]\ncount = 1\ncolor = \"#FF8000\"\n", "c.toml");
    EXPECT_EQ(scene.species[0].color, (std::array<float, 3>{1.0f, 128 / 255.0f, 0.0f}));
}

TEST(SceneIoParse, EmptyMixingMeansOneForEveryPair) {
    Scene scene = parseScene("[[species]]\ncount = 1\n[[species]]\ncount = 1\n[interaction]\nmixing = []\n", "m.toml");
    EXPECT_TRUE(scene.interaction.mixing.empty());
    EXPECT_EQ(scene.mixing(0, 1), 1.0);
}

TEST(SceneIoParse, UnknownKeyMessageSuggestsTheAllowedOnes) {
    try {
        parseScene("[[species]]\ncount = 1\nmas = 2\n", "typo.toml");
        FAIL() << "no InputError";
    } catch (const InputError& error) {
        std::string message = error.what();
        EXPECT_NE(message.find("did you mean 'mass'"), std::string::npos) << message;
        EXPECT_NE(message.find("name, count, mass, radius, sigma, epsilon, color"), std::string::npos) << message;
    }
}

// ---- files --------------------------------------------------------------------------------------------

TEST(SceneIoFiles, UnreadableFileNamesThePath) {
    std::string path = (scratchDir("missing") / "nope.toml").string();
    try {
        loadScene(path);
        FAIL() << "no InputError";
    } catch (const InputError& error) {
        EXPECT_NE(std::string(error.what()).find("cannot read '" + path + "'"), std::string::npos) << error.what();
    }
    EXPECT_THROW(loadScene(scratchDir("directory").string()), InputError);
}

TEST(SceneIoFiles, ErrorsInAFileNameIt) {
    std::filesystem::path path = scratchDir("bad_file") / "bad.toml";
    writeText(path, "[[species]]\ncount = 1\nmass = -1\n");
    try {
        loadScene(path.string());
        FAIL() << "no InputError";
    } catch (const InputError& error) {
        EXPECT_EQ(std::string(error.what()).rfind(path.string() + ":3: species[0].mass: ", 0), 0u) << error.what();
    }
}

TEST(SceneIoFiles, RelativeParticlesFileIsResolvedAgainstTheSceneDirectory) {
    std::filesystem::path dir = scratchDir("particles");
    writeText(dir / "scene.toml", "[[species]]\ncount = 1\n[init]\nparticles = \"data/start.csv\"\n");
    writeText(dir / "absolute.toml", "[[species]]\ncount = 1\n[init]\nparticles = \"/elsewhere/start.csv\"\n");
    EXPECT_EQ(loadScene((dir / "scene.toml").string()).init.particlesFile, (dir / "data/start.csv").string());
    EXPECT_EQ(loadScene((dir / "absolute.toml").string()).init.particlesFile, "/elsewhere/start.csv");
    // parseScene has no directory to resolve against: the path stays as written.
    EXPECT_EQ(parseScene("[[species]]\ncount = 1\n[init]\nparticles = \"p.csv\"\n", "x").init.particlesFile, "p.csv");
}

TEST(SceneIoFiles, SaveThenLoadKeepsEveryFieldAndTheParticleFile) {
    std::filesystem::path dir = scratchDir("save");
    writeText(dir / "scene.toml", "[[species]]\ncount = 1\n[init]\nparticles = \"data/start.csv\"\n");
    Scene scene = loadScene((dir / "scene.toml").string());
    std::filesystem::create_directories(dir / "out");
    std::string saved = (dir / "out" / "copy.toml").string();

    saveScene(scene, saved);
    Scene reloaded = loadScene(saved);
    expectSameScene(reloaded, scene);
    EXPECT_FALSE(std::filesystem::exists(saved + ".tmp-" + std::to_string(::getpid())));

    // A particle path relative to the working directory is rewritten relative to the new file.
    scene.init.particlesFile = "data/start.csv";
    saveScene(scene, saved);
    reloaded = loadScene(saved);
    EXPECT_EQ(std::filesystem::absolute(reloaded.init.particlesFile).lexically_normal(),
              std::filesystem::absolute(scene.init.particlesFile).lexically_normal());
    reloaded.init.particlesFile = scene.init.particlesFile;
    expectSameScene(reloaded, scene);

    EXPECT_THROW(saveScene(scene, (dir / "no_such_dir" / "x.toml").string()), InputError);
}

// ---- bad input: one row per way a scene can be wrong ---------------------------------------------------
//
// The offending line of each text is marked "# <-"; the error must point at it (no mark: the error
// has no line, e.g. a missing section). Every message must start "bad.toml:<line>: <key>: ".

struct BadScene {
    const char* name;
    std::string text;
    const char* key;
    const char* fragment;  // a phrase the message must contain ("" for none)
};

std::ostream& operator<<(std::ostream& out, const BadScene& bad) { return out << bad.name; }

const std::string kOne = "[[species]]\ncount = 10\n";  // a valid minimal scene to extend

long markedLine(const std::string& text) {
    size_t mark = text.find("# <-");
    if (mark == std::string::npos) return 0;
    return 1 + static_cast<long>(std::count(text.begin(), text.begin() + static_cast<long>(mark), '\n'));
}

class SceneIoBadInput : public testing::TestWithParam<BadScene> {};

TEST_P(SceneIoBadInput, IsRefusedWithFileLineAndKey) {
    const BadScene& bad = GetParam();
    try {
        parseScene(bad.text, "bad.toml");
        FAIL() << "accepted:\n" << bad.text;
    } catch (const InputError& error) {
        std::string message = error.what();
        long line = markedLine(bad.text);
        std::string expected = "bad.toml" + (line > 0 ? ":" + std::to_string(line) : std::string()) + ": ";
        if (*bad.key) expected += std::string(bad.key) + ": ";
        EXPECT_EQ(message.rfind(expected, 0), 0u) << "message: " << message << "\nexpected start: " << expected;
        EXPECT_NE(message.find(bad.fragment), std::string::npos) << "message: " << message;
    }
}

INSTANTIATE_TEST_SUITE_P(
    AllCases, SceneIoBadInput,
    testing::Values(
        // Syntax and structure
        BadScene{"MalformedToml", kOne + "mass = = 1 # <-\n", "", ""},
        BadScene{"DuplicateKey", kOne + "count = 11 # <-\n", "", ""},
        BadScene{"UnknownTable", kOne + "[boxes] # <-\n", "boxes", "allowed: box, species, interaction"},
        BadScene{"UnknownRootKey", "dt = 0.1 # <-\n" + kOne, "dt", "allowed: box"},
        BadScene{"UnknownBoxKey", kOne + "[box]\nsizes = [1, 1, 1] # <-\n", "box.sizes",
                 "allowed: size, wall_restitution"},
        BadScene{"UnknownSpeciesKey", kOne + "[[species]]\ncount = 1\nname = \"B\"\nradios = 1 # <-\n",
                 "species[1].radios", "did you mean 'radius'"},
        BadScene{"UnknownInteractionKey", kOne + "[interaction]\nmix = 1 # <-\n", "interaction.mix", "mixing"},
        BadScene{"UnknownIntegratorKey", kOne + "[integrator]\nsteps = 1 # <-\n", "integrator.steps", "method"},
        BadScene{"UnknownDevicesKey", kOne + "[devices]\ngpu = 2 # <-\n", "devices.gpu", "gpus"},
        BadScene{"ZeroGpus", kOne + "[devices]\ngpus = 0 # <-\n", "devices.gpus", "GPU count"},
        BadScene{"GpusNotAuto", kOne + "[devices]\ngpus = \"all\" # <-\n", "devices.gpus", "auto"},
        BadScene{"UnknownExchange", kOne + "[devices]\nexchange = \"mpi\" # <-\n", "devices.exchange",
                 "dts, dta, da, nccl"},
        BadScene{"UnknownThermostatKey", kOne + "[thermostat]\ntarget = 1 # <-\n", "thermostat.target", "kind"},
        BadScene{"UnknownInitKey", kOne + "[init]\nfile = \"x\" # <-\n", "init.file", "particles"},
        BadScene{"BoxNotATable", "box = 10 # <-\n" + kOne, "box", "must be a table"},
        BadScene{"NoSpecies", "[box]\nsize = [10, 10, 10]\n", "species", "required"},
        BadScene{"SpeciesNotAnArrayOfTables", "[species] # <-\ncount = 10\n", "species", "[[species]]"},
        BadScene{"SpeciesEmptyArray", "species = [] # <-\n", "species", "required"},
        BadScene{"SpeciesMissingCount", "[[species]] # <-\nname = \"A\"\n[[species]]\nname = \"B\"\ncount = 5\n",
                 "species[0].count", "missing"},
        // Wrong types
        BadScene{"MassNotANumber", kOne + "mass = \"heavy\" # <-\n", "species[0].mass", "must be a number"},
        BadScene{"CountNotAnInteger", "[[species]]\ncount = 10.5 # <-\n", "species[0].count", "must be an integer"},
        BadScene{"NameNotAString", kOne + "name = 3 # <-\n", "species[0].name", "must be a string"},
        BadScene{"AdaptiveNotABool", kOne + "[integrator]\nmethod = \"dp5\"\nadaptive = 1 # <-\n",
                 "integrator.adaptive", "true or false"},
        BadScene{"MethodNotAString", kOne + "[integrator]\nmethod = 4 # <-\n", "integrator.method", "must be a string"},
        BadScene{"SeedNotAnInteger", kOne + "[init]\nseed = 1.5 # <-\n", "init.seed", "must be an integer"},
        BadScene{"ParticlesNotAString", kOne + "[init]\nparticles = 3 # <-\n", "init.particles", "must be a string"},
        // Species values
        BadScene{"MassZero", kOne + "mass = 0 # <-\n", "species[0].mass", "> 0"},
        BadScene{"MassNegativeSecondSpecies", kOne + "[[species]]\nname = \"B\"\ncount = 5\nmass = -1.0 # <-\n",
                 "species[1].mass", "> 0"},
        BadScene{"MassInfinite", kOne + "mass = inf # <-\n", "species[0].mass", "finite"},
        BadScene{"RadiusZero", kOne + "radius = 0.0 # <-\n", "species[0].radius", "> 0"},
        BadScene{"SigmaNegative", kOne + "sigma = -1 # <-\n", "species[0].sigma", "> 0"},
        BadScene{"EpsilonNegative", kOne + "epsilon = -0.5 # <-\n", "species[0].epsilon", ">= 0"},
        BadScene{"CountNegative", kOne + "[[species]]\nname = \"B\"\ncount = -1 # <-\n", "species[1].count", ">= 0"},
        BadScene{"TotalCountZero", "[[species]] # <-\ncount = 0\n[[species]]\nname = \"B\"\ncount = 0\n", "species",
                 "total particle count is 0"},
        BadScene{"NameEmpty", kOne + "name = \"\" # <-\n", "species[0].name", "empty"},
        BadScene{"NameDuplicated", kOne + "name = \"X\"\n[[species]]\ncount = 1\nname = \"X\" # <-\n",
                 "species[1].name", "duplicate"},
        BadScene{"DefaultNameDuplicated", kOne + "[[species]]\ncount = 1\nname = \"A\" # <-\n", "species[1].name",
                 "duplicate"},
        BadScene{"ColorName", kOne + "color = \"red\" # <-\n", "species[0].color", "#rrggbb"},
        BadScene{"ColorShort", kOne + "color = \"#12345\" # <-\n", "species[0].color", "#rrggbb"},
        BadScene{"ColorNotHex", kOne + "color = \"#gg0000\" # <-\n", "species[0].color", "#rrggbb"},
        BadScene{"ColorSignedHex", kOne + "color = \"#+10000\" # <-\n", "species[0].color", "#rrggbb"},
        // Box
        BadScene{"BoxSizeTwoNumbers", kOne + "[box]\nsize = [10, 10] # <-\n", "box.size", "3 numbers"},
        BadScene{"BoxSizeScalar", kOne + "[box]\nsize = 10 # <-\n", "box.size", "3 numbers"},
        BadScene{"BoxSizeZero", kOne + "[box]\nsize = [10, 10, 0] # <-\n", "box.size", "positive"},
        BadScene{"BoxSizeNotANumber", kOne + "[box]\nsize = [10, 10,\n  \"ten\"] # <-\n", "box.size[2]", "number"},
        BadScene{"WallRestitutionAboveOne", kOne + "[box]\nwall_restitution = 1.5 # <-\n", "box.wall_restitution",
                 "[0, 1]"},
        BadScene{"WallRestitutionNegative", kOne + "[box]\nwall_restitution = -0.1 # <-\n", "box.wall_restitution",
                 "[0, 1]"},
        // Interaction
        BadScene{"RestitutionAboveOne", kOne + "[interaction]\nrestitution = 1.01 # <-\n", "interaction.restitution",
                 "[0, 1]"},
        BadScene{"CutoffNegative", kOne + "[interaction]\ncutoff = -2.5 # <-\n", "interaction.cutoff", ">= 0"},
        BadScene{"ShiftUnknown", kOne + "[interaction]\nshift = \"both\" # <-\n", "interaction.shift",
                 "none, energy, force"},
        BadScene{"MixingTooBig", kOne + "[interaction]\nmixing = [[1.0, 0.5], [0.5, 1.0]] # <-\n", "interaction.mixing",
                 "1x1"},
        BadScene{"MixingNotAnArray", kOne + "[interaction]\nmixing = 0.5 # <-\n", "interaction.mixing", "1x1"},
        BadScene{
            "MixingRowTooShort",
            kOne + "[[species]]\nname = \"B\"\ncount = 1\n[interaction]\nmixing = [\n  [1.0, 0.5],\n  [0.5]] # <-\n",
            "interaction.mixing[1]", "2x2"},
        BadScene{
            "MixingAsymmetric",
            kOne +
                "[[species]]\nname = \"B\"\ncount = 1\n[interaction]\nmixing = [\n  [1.0, 0.5],\n  [0.4, 1.0]] # <-\n",
            "interaction.mixing[1][0]", "symmetric"},
        BadScene{"MixingNegative",
                 kOne + "[[species]]\nname = \"B\"\ncount = 1\n[interaction]\nmixing = [\n  [1.0, -0.5], # <-\n  "
                        "[-0.5, 1.0]]\n",
                 "interaction.mixing[0][1]", ">= 0"},
        BadScene{"MixingNotANumber", kOne + "[interaction]\nmixing = [[\"one\"]] # <-\n", "interaction.mixing[0][0]",
                 "number"},
        BadScene{"GravityTwoNumbers", kOne + "[interaction]\ngravity = [0, -1] # <-\n", "interaction.gravity",
                 "3 numbers"},
        BadScene{"GravityNotANumber", kOne + "[interaction]\ngravity = [0, 0, \"down\"] # <-\n",
                 "interaction.gravity[2]", "number"},
        BadScene{"ElasticBelowSpeedNegative", kOne + "[interaction]\nelastic_below_speed = -1e-3 # <-\n",
                 "interaction.elastic_below_speed", ">= 0"},
        BadScene{"MaxCollisionRoundsZero", kOne + "[interaction]\nmax_collision_rounds = 0 # <-\n",
                 "interaction.max_collision_rounds", ">= 1"},
        BadScene{"MaxCollisionRoundsAboveTheLimit", kOne + "[interaction]\nmax_collision_rounds = 5000 # <-\n",
                 "interaction.max_collision_rounds", "<= 4096"},
        BadScene{"ContactSweepsNegative", kOne + "[interaction]\ncontact_sweeps = -3 # <-\n",
                 "interaction.contact_sweeps", ">= 0"},
        BadScene{"ContactListingsNegative", kOne + "[interaction]\ncontact_listings = -1 # <-\n",
                 "interaction.contact_listings", "0 to 32"},
        BadScene{"ContactListingsAboveTheLimit", kOne + "[interaction]\ncontact_listings = 33 # <-\n",
                 "interaction.contact_listings", "0 to 32"},
        BadScene{"MaxCollisionRoundsHuge", kOne + "[interaction]\nmax_collision_rounds = 9999999999 # <-\n",
                 "interaction.max_collision_rounds", "<="},
        // Integrator
        BadScene{"MethodUnknown", kOne + "[integrator]\nmethod = \"rk5\" # <-\n", "integrator.method",
                 "euler, rk2, rk4, dp5, hairer10, verlet"},
        BadScene{"DtZero", kOne + "[integrator]\ndt = 0 # <-\n", "integrator.dt", "> 0"},
        BadScene{"DtNegative", kOne + "[integrator]\ndt = -1e-3 # <-\n", "integrator.dt", "> 0"},
        BadScene{"DtInfinite", kOne + "[integrator]\ndt = inf # <-\n", "integrator.dt", "finite"},
        BadScene{"DtNan", kOne + "[integrator]\ndt = nan # <-\n", "integrator.dt", "finite"},
        BadScene{"PrecisionUnknown", kOne + "[integrator]\nprecision = \"fp16\" # <-\n", "integrator.precision",
                 "fp32, fp64"},
        BadScene{"AdaptiveWithRk4", kOne + "[integrator]\nmethod = \"rk4\"\nadaptive = true # <-\n",
                 "integrator.adaptive", "dp5"},
        BadScene{"AdaptiveWithDefaultMethod", kOne + "[integrator]\nadaptive = true # <-\n", "integrator.adaptive",
                 "dp5"},
        BadScene{"ToleranceZero", kOne + "[integrator]\ntolerance = 0.0 # <-\n", "integrator.tolerance", "> 0"},
        // Thermostat
        BadScene{"ThermostatKindUnknown", kOne + "[thermostat]\nkind = \"nose-hoover\" # <-\n", "thermostat.kind",
                 "bussi, rescale, none"},
        BadScene{"ThermostatTemperatureNegative", kOne + "[thermostat]\ntemperature = -1 # <-\n",
                 "thermostat.temperature", ">= 0"},
        BadScene{"ThermostatTauZero", kOne + "[thermostat]\ntau = 0 # <-\n", "thermostat.tau", "> 0"},
        // Init
        BadScene{"InitTemperatureNegative", kOne + "[init]\ntemperature = -0.1 # <-\n", "init.temperature", ">= 0"},
        BadScene{"SeedNegative", kOne + "[init]\nseed = -1 # <-\n", "init.seed", ">= 0"},
        BadScene{"PlacementUnknown", kOne + "[init]\nplacement = \"grid\" # <-\n", "init.placement", "lattice, random"},
        // More particles than fit
        BadScene{"PackingFractionTooHigh", "[box]\nsize = [10, 10, 10]\n[[species]] # <-\ncount = 1000\n", "species",
                 "packing fraction 0.524 exceeds the limit 0.45"},
        BadScene{"PackingFractionOfAllSpecies",
                 "[box]\nsize = [10, 10, 10]\n[[species]] # <-\ncount = 500\n[[species]]\ncount = 500\nname = \"B\"\n",
                 "species", "packing fraction"},
        BadScene{"DiameterExceedsBox", "[box]\nsize = [2, 10, 10]\n[[species]]\ncount = 1\nradius = 1.5 # <-\n",
                 "species[0].radius", "smallest box edge 2"},
        BadScene{"DefaultRadiusExceedsBox", "[box]\nsize = [0.9, 10, 10]\n[[species]] # <-\ncount = 1\n",
                 "species[0].radius", "diameter 1"}),
    [](const testing::TestParamInfo<BadScene>& info) { return std::string(info.param.name); });
