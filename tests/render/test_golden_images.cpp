// Golden images: the hard_spheres preset's initial state rendered at 320x240 in each colour mode
// must match assets/golden/ within a tolerance: mean absolute difference below 1.0 (0-255 scale)
// and fewer than 0.5% of pixels off by more than 24 in any channel (room for rasteriser rounding
// across Mesa versions, none for a wrong colour, size or camera). scripts/update-goldens
// regenerates them on purpose (COREBOX_UPDATE_GOLDENS=1).
#include <cstdlib>
#include <string>

#include "image_io.h"
#include "initial_conditions.h"
#include "offscreen_target.h"
#include "particle_renderer.h"
#include "render_fixture.h"
#include "scene_io.h"
#include "scene_drawing.h"

using namespace corebox;
using namespace corebox::testing;

namespace {

Image renderPreset(const std::string& preset, ColorMode mode) {
    const Scene scene = loadScene(std::string(COREBOX_SOURCE_DIR) + "/assets/" + preset + ".toml");
    std::vector<ParticleInstance> instances;
    buildInstances(makeInitialState(scene), scene, mode, instances);
    ParticleRenderer renderer;
    renderer.upload(instances.data(), instances.size());
    OffscreenTarget target(320, 240);
    OrbitCamera camera;
    const std::array<float, 3> box{float(scene.box.size[0]), float(scene.box.size[1]), float(scene.box.size[2])};
    camera.frameBox({box[0], box[1], box[2]}, 320.0f / 240.0f);
    target.bind();
    renderer.render(camera, box, renderStyleFor(scene, mode), 320, 240);
    Image img{320, 240, {}};
    target.readPixels(img.rgba);
    return img;
}

void compareWithGolden(const std::string& name, const Image& img) {
    const std::string path = std::string(COREBOX_SOURCE_DIR) + "/assets/golden/" + name + ".png";
    const char* update = std::getenv("COREBOX_UPDATE_GOLDENS");
    if (update && std::string(update) == "1") {
        writePng(path, img);
        std::printf("updated %s\n", path.c_str());
        return;
    }
    const Image golden = readPng(path);
    ASSERT_EQ(golden.width, img.width);
    ASSERT_EQ(golden.height, img.height);
    double sum = 0;
    size_t off = 0;
    for (size_t p = 0; p < img.rgba.size(); p += 4) {
        int worst = 0;
        for (int c = 0; c < 3; ++c) {
            const int d = std::abs(int(img.rgba[p + size_t(c)]) - int(golden.rgba[p + size_t(c)]));
            sum += d;
            worst = std::max(worst, d);
        }
        if (worst > 24) ++off;
    }
    const double pixels = double(img.rgba.size() / 4);
    const double meanDiff = sum / (3 * pixels);
    const double offFraction = double(off) / pixels;
    ::testing::Test::RecordProperty(name + "_mean_abs_diff", std::to_string(meanDiff));
    ::testing::Test::RecordProperty(name + "_fraction_off", std::to_string(offFraction));
    EXPECT_LT(meanDiff, 1.0) << name << ": run scripts/update-goldens only if the change is intended";
    EXPECT_LT(offFraction, 0.005) << name;
}

}  // namespace

TEST_F(RenderTest, HardSpheresBySpeciesMatchesItsGolden) {
    compareWithGolden("hard_spheres_species", renderPreset("hard_spheres", ColorMode::Species));
}

TEST_F(RenderTest, HardSpheresBySpeedMatchesItsGolden) {
    compareWithGolden("hard_spheres_speed", renderPreset("hard_spheres", ColorMode::Speed));
}

TEST_F(RenderTest, GoldenComparisonRejectsAChangedImage) {
    // The tolerance must not be so loose that a visibly different frame passes: a shifted camera.
    Image img = renderPreset("hard_spheres", ColorMode::Species);
    const Image golden = readPng(std::string(COREBOX_SOURCE_DIR) + "/assets/golden/hard_spheres_species.png");
    std::vector<uint8_t> shifted(img.rgba.size());
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x)
            for (int c = 0; c < 4; ++c)
                shifted[(size_t(y) * 320 + size_t(x)) * 4 + size_t(c)] = img.rgba[(size_t(y) * 320 + size_t(std::max(0, x - 3))) * 4 + size_t(c)];
    size_t off = 0;
    for (size_t p = 0; p < shifted.size(); p += 4) {
        int worst = 0;
        for (int c = 0; c < 3; ++c) worst = std::max(worst, std::abs(int(shifted[p + size_t(c)]) - int(golden.rgba[p + size_t(c)])));
        if (worst > 24) ++off;
    }
    EXPECT_GT(double(off) / (320.0 * 240.0), 0.005);
}
