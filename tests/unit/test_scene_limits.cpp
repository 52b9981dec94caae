// Validation of values a step cannot carry (scene_validation.cpp, checkScales) and the memory
// estimate (memory_estimate.h). Each class of issue 11: non-finite values (inf passes "> 0"), values
// each representable whose products overflow (epsilon 1e300, gravity 1e308, kT 1e308), values out of
// fp32's range, counts whose sum overflows, and scenes too large for this machine (a huge count, a
// very long box for the lattice placement) -- all InputError naming the key, never bad_alloc.
#include <gtest/gtest.h>

#include <limits>
#include <string>

#include "errors.h"
#include "initial_conditions.h"
#include "memory_estimate.h"
#include "scene_validation.h"

using namespace corebox;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

Scene smallGas() {
    Scene scene;
    SpeciesDef s;
    s.count = 20;
    scene.species = {s};
    return scene;
}

// The message of the InputError validateScene throws, "" when it accepts the scene.
std::string problemOf(const Scene& scene) {
    try {
        validateScene(scene, SceneLocations("test.toml"));
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

void expectRefused(const Scene& scene, const std::string& key) {
    const std::string message = problemOf(scene);
    EXPECT_NE(message.find(key), std::string::npos) << "expected a refusal naming " << key << ", got: '" << message << "'";
}

}  // namespace

TEST(SceneLimits, AValidSceneIsAccepted) { EXPECT_EQ(problemOf(smallGas()), ""); }

TEST(SceneLimits, NonFiniteValuesAreRefusedEvenWhereTheyPassPositivityChecks) {
    for (double bad : {kInf, kNaN, -kInf}) {
        Scene s = smallGas();
        s.integrator.dt = bad;
        expectRefused(s, "integrator.dt");
        s = smallGas();
        s.species[0].mass = bad;
        expectRefused(s, "species[0].mass");
        s = smallGas();
        s.species[0].epsilon = bad;
        expectRefused(s, "species[0].epsilon");
        s = smallGas();
        s.box.size[1] = bad;
        expectRefused(s, "box.size");
        s = smallGas();
        s.interaction.gravity[2] = bad;
        expectRefused(s, "interaction.gravity");
        s = smallGas();
        s.thermostat.temperature = bad;
        expectRefused(s, "thermostat.temperature");
        s = smallGas();
        s.init.temperature = bad;
        expectRefused(s, "init.temperature");
        s = smallGas();
        s.interaction.cutoff = bad;
        expectRefused(s, "interaction.cutoff");
    }
}

TEST(SceneLimits, ValuesWhoseProductsOverflowAreInputErrors) {
    Scene s = smallGas();
    s.species[0].epsilon = 1e300;
    expectRefused(s, "species[0].epsilon");
    s = smallGas();
    s.interaction.gravity = {0, 0, -1e308};
    expectRefused(s, "interaction.gravity");
    s = smallGas();
    s.init.temperature = 1e308;
    expectRefused(s, "init.temperature");
    s = smallGas();
    s.integrator.dt = 1e308;
    expectRefused(s, "integrator.dt");
    // Each factor modest, the product not: N kT with N = 1e6 and kT = 1e146.
    s = smallGas();
    s.species[0].count = 1000000;
    s.box.size = {1000, 1000, 1000};
    s.thermostat.temperature = 1e146;
    s.init.temperature = 0;
    expectRefused(s, "thermostat.temperature");
}

TEST(SceneLimits, Fp32RangeIsNarrowerThanFp64) {
    Scene s = smallGas();
    s.species[0].mass = 1e-40;
    s.init.temperature = 0;
    s.thermostat.temperature = 0;
    s.species[0].epsilon = 0;
    EXPECT_EQ(problemOf(s), "") << "1e-40 is a fine mass in fp64 for hard spheres at rest";
    s.integrator.precision = Precision::Fp32;
    expectRefused(s, "species[0].mass");
    s = smallGas();
    s.species[0].epsilon = 1e20;
    s.integrator.precision = Precision::Fp32;
    expectRefused(s, "species[0].epsilon");
}

TEST(SceneLimits, CountsWhoseSumOverflowsAreRefused) {
    Scene s = smallGas();
    SpeciesDef b;
    b.name = "B";
    s.species[0].count = std::numeric_limits<int64_t>::max();
    b.count = std::numeric_limits<int64_t>::max();
    s.species.push_back(b);
    expectRefused(s, "species");
}

TEST(SceneLimits, ALatticeForAnAstronomicallyLongBoxIsRefusedBeforeItsIntegerCount) {
    Scene s = smallGas();
    s.box.size = {1e100, 10, 10};
    expectRefused(s, "box.size");
    s.init.placement = Placement::Random;
    EXPECT_EQ(problemOf(s), "") << "random placement has no lattice to count";
}

TEST(MemoryEstimate, GrowsWithTheCountAndWithTheLatticeOfALongBox) {
    Scene s = smallGas();
    const double small = estimatedHostBytes(s);
    s.species[0].count = 2000;
    s.box.size = {100, 100, 100};
    EXPECT_GT(estimatedHostBytes(s), 50 * small);
    Scene longBox = smallGas();
    longBox.box.size = {1e15, 10, 10};
    EXPECT_GT(latticeSiteCount(longBox), 1e9);
    EXPECT_GT(estimatedHostBytes(longBox), 8e9);
    EXPECT_EQ(formatBytes(1536), "1.5 KiB");
}

TEST(MemoryEstimate, SetupRefusesWhatCannotFitWithTheSizesNamed) {
    ASSERT_GT(physicalMemoryBytes(), 0);
    Scene huge = smallGas();
    huge.species[0].count = int64_t(1e14);  // ~50 PiB: more than any host
    huge.box.size = {1e6, 1e6, 1e6};
    try {
        (void)makeInitialState(huge);
        FAIL() << "a scene of 1e14 particles was set up";
    } catch (const InputError& e) {
        const std::string message = e.what();
        EXPECT_NE(message.find("100000000000000 particles need about"), std::string::npos) << message;
        EXPECT_NE(message.find("PiB"), std::string::npos) << message;
        EXPECT_NE(message.find("this machine has"), std::string::npos) << message;
    }
    Scene longBox = smallGas();
    longBox.box.size = {1e18, 10, 10};  // ~1e12 lattice sites: 8 TB for the shuffle
    try {
        (void)makeInitialState(longBox);
        FAIL() << "a lattice of 1e12 sites was set up";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("placement = \"random\""), std::string::npos) << e.what();
    }
}
