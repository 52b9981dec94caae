// One packing rule for scene validation and the initial placement: a scene that validates can be
// placed on its lattice, and a scene the placement cannot fill is refused when it is read, with the
// same message.
#include <gtest/gtest.h>

#include <string>

#include "errors.h"
#include "initial_conditions.h"
#include "packing.h"
#include "scene_io.h"
#include "scene_validation.h"

using namespace corebox;

namespace {

// The message of the InputError `f` throws, or "" when it throws none.
template <class F>
std::string errorOf(F&& f) {
    try {
        f();
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

// One big core among many small ones (hard spheres): a packing fraction under 1 %, yet the lattice that places
// 1000 particles in this box has spacing 1, below the big cores' contact distance 2.
std::string bigAmongSmall(const std::string& placement) {
    return "[box]\nsize = [10, 10, 10]\n"
           "[[species]]\nname = \"big\"\ncount = 2\nradius = 1.0\nepsilon = 0.0\n"
           "[[species]]\nname = \"small\"\ncount = 998\nradius = 0.1\nepsilon = 0.0\n"
           "[init]\nplacement = \"" + placement + "\"\n";
}

Scene cubic(int64_t count, double radius, std::array<double, 3> box) {
    Scene scene;
    SpeciesDef s;
    s.count = count;
    s.radius = radius;
    s.epsilon = 0;
    scene.species = {s};
    scene.box.size = box;
    return scene;
}

}  // namespace

TEST(Packing, LatticeThatCannotHoldTheCoresIsRefusedWhenTheSceneIsRead) {
    const std::string message = errorOf([] { parseScene(bigAmongSmall("lattice"), "mixed.toml"); });
    EXPECT_NE(message.find("mixed.toml:3: species: more particles than fit"), std::string::npos) << message;
    EXPECT_NE(message.find("largest contact distance 2"), std::string::npos) << message;
}

TEST(Packing, RandomPlacementOfTheSameCoresIsAccepted) {
    const Scene scene = parseScene(bigAmongSmall("random"), "mixed.toml");
    EXPECT_EQ(makeInitialState(scene).size(), 1000u);
}

TEST(Packing, ValidationAndPlacementAgreeOnEveryScene) {
    // Counts, radii and box shapes around the limits of all three rules.
    for (int64_t count : {1, 8, 27, 100, 101, 400, 500, 860, 1000}) {
        for (double radius : {0.3, 0.45, 0.5, 0.55, 0.62}) {
            for (std::array<double, 3> box : {std::array<double, 3>{10, 10, 10}, {10, 10, 1.0}, {20, 5, 5}, {7, 7, 7}}) {
                const Scene scene = cubic(count, radius, box);
                const std::string validated = errorOf([&] { validateScene(scene, SceneLocations()); });
                const std::string placed = errorOf([&] { makeInitialState(scene); });
                SCOPED_TRACE("count " + std::to_string(count) + ", radius " + std::to_string(radius) + ", box " +
                             std::to_string(box[0]) + "x" + std::to_string(box[1]) + "x" + std::to_string(box[2]));
                EXPECT_EQ(validated.empty(), placed.empty()) << "validation: " << validated << "\nplacement: " << placed;
                if (!validated.empty()) {
                    EXPECT_EQ(validated, placed);
                }
            }
        }
    }
}

// A lattice that the particles fill exactly (7^3 = 343 spheres of diameter 1 in a 7.7 cube, packing
// fraction 0.39) is accepted and placed with spacing 1.1, whatever the rounding of L cbrt(N / V).
TEST(Packing, AnExactlyFilledLatticeIsAccepted) {
    for (int side : {4, 5, 7, 10}) {
        const Scene scene = cubic(int64_t(side) * side * side, 0.5, {1.1 * side, 1.1 * side, 1.1 * side});
        EXPECT_FALSE(packingProblem(scene).has_value()) << side << "^3: " << packingProblem(scene)->message;
        EXPECT_EQ(latticeSites(scene), (std::array<int64_t, 3>{side, side, side}));
    }
    const Scene reported = cubic(343, 0.5, {7.7, 7.7, 7.7});
    EXPECT_EQ(latticeSites(reported), (std::array<int64_t, 3>{7, 7, 7}));
    EXPECT_FALSE(packingProblem(reported).has_value());
}

TEST(Packing, LatticeHasASiteForEveryParticle) {
    for (int64_t count : {1, 7, 64, 65, 1000, 1234}) {
        const std::array<int64_t, 3> sites = latticeSites(cubic(count, 0.1, {13, 5, 8}));
        EXPECT_GE(sites[0] * sites[1] * sites[2], count);
    }
}
