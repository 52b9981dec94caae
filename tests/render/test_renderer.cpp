// Renderer on llvmpipe: pixels at projected sphere centres have the species colour (lit), the
// background elsewhere, and nearer spheres hide farther ones whatever the draw order.
#include <glm/glm.hpp>

#include "image_io.h"
#include "offscreen_target.h"
#include "orbit_camera.h"
#include "particle_renderer.h"
#include "render_fixture.h"

using namespace corebox;
using namespace corebox::testing;

namespace {

constexpr int kWidth = 320, kHeight = 240;

struct Pixel {
    int r, g, b;
};

Pixel at(const Image& img, glm::vec2 p) {
    const size_t i = (size_t(int(p.y)) * size_t(img.width) + size_t(int(p.x))) * 4;
    return {img.rgba[i], img.rgba[i + 1], img.rgba[i + 2]};
}

RenderStyle plainStyle() {
    RenderStyle style;
    style.palette = {{0.9f, 0.1f, 0.1f}, {0.1f, 0.85f, 0.1f}, {0.15f, 0.2f, 0.95f}};
    style.showLegend = false;
    style.showBox = false;
    return style;
}

Image draw(const std::vector<ParticleInstance>& particles, const OrbitCamera& camera, const RenderStyle& style) {
    ParticleRenderer renderer;
    OffscreenTarget target(kWidth, kHeight);
    renderer.upload(particles.data(), particles.size());
    target.bind();
    renderer.render(camera, {10, 10, 10}, style, kWidth, kHeight);
    Image img{kWidth, kHeight, {}};
    target.readPixels(img.rgba);
    return img;
}

}  // namespace

TEST_F(RenderTest, SphereCentresShowTheirLitSpeciesColourOnTheBackground) {
    OrbitCamera camera;
    camera.frameBox({10, 10, 10}, float(kWidth) / kHeight);
    const std::vector<ParticleInstance> particles = {{2, 5, 5, 1.0f, 0}, {5, 5, 5, 1.0f, 1}, {8, 5, 5, 1.0f, 2}};
    const RenderStyle style = plainStyle();
    const Image img = draw(particles, camera, style);
    for (int k = 0; k < 3; ++k) {
        const glm::vec2 p = projectToPixel(camera, {particles[size_t(k)].x, particles[size_t(k)].y, particles[size_t(k)].z}, kWidth, kHeight);
        const Pixel c = at(img, p);
        const int channel[3] = {c.r, c.g, c.b};
        // The species' own channel dominates and the sphere is lit (brighter than ambient alone).
        for (int other = 0; other < 3; ++other) {
            if (other != k) {
                EXPECT_GT(channel[k], channel[other] + 60) << "sphere " << k << " at " << p.x << "," << p.y;
            }
        }
        EXPECT_GT(channel[k], int(255 * style.palette[size_t(k)][size_t(k)] * 0.45f)) << "sphere " << k;
    }
    // Corners are background, exactly the clear colour.
    for (glm::vec2 corner : {glm::vec2(2, 2), glm::vec2(kWidth - 3, 2), glm::vec2(2, kHeight - 3), glm::vec2(kWidth - 3, kHeight - 3)}) {
        const Pixel c = at(img, corner);
        EXPECT_EQ(c.r, int(std::lround(style.background[0] * 255)));
        EXPECT_EQ(c.g, int(std::lround(style.background[1] * 255)));
        EXPECT_EQ(c.b, int(std::lround(style.background[2] * 255)));
    }
}

TEST_F(RenderTest, NearerSpheresHideFartherOnesWhateverTheDrawOrder) {
    OrbitCamera camera;
    camera.frameBox({10, 10, 10}, float(kWidth) / kHeight);
    const glm::vec3 toCamera = glm::normalize(camera.eye() - camera.target);
    const glm::vec3 nearCentre = camera.target + 2.0f * toCamera, farCentre = camera.target - 2.0f * toCamera;
    const ParticleInstance nearRed{nearCentre.x, nearCentre.y, nearCentre.z, 1.0f, 0};
    const ParticleInstance farBlue{farCentre.x, farCentre.y, farCentre.z, 1.5f, 2};
    const glm::vec2 centre = projectToPixel(camera, camera.target, kWidth, kHeight);
    for (const auto& order : {std::vector<ParticleInstance>{nearRed, farBlue}, std::vector<ParticleInstance>{farBlue, nearRed}}) {
        const Pixel c = at(draw(order, camera, plainStyle()), centre);
        EXPECT_GT(c.r, c.b + 60) << "the far blue sphere shows through the near red one";
    }
    // The far sphere is larger: its rim around the near one is blue.
    const glm::vec2 rim = projectToPixel(camera, farCentre + 1.3f * glm::normalize(glm::cross(toCamera, glm::vec3(0, 0, 1))), kWidth, kHeight);
    const Pixel c = at(draw({nearRed, farBlue}, camera, plainStyle()), rim);
    EXPECT_GT(c.b, c.r + 60);
}

// RenderStyle::exactDepth false draws each sphere at the depth of its point nearest the eye. Spheres that do
// not intersect hide each other as with exact depth: a heap of touching balls (a 5 x 5 x 3 lattice of
// diameter 1 spaced 1.0, as hard cores rest, with a ball of twice the radius on top) gives the same colour
// at every pixel (llvmpipe: all 3,548 drawn pixels) but, at most, a few where rounding decides a tie.
// Intersecting spheres show the nearer one whole: where the near red sphere reaches into the larger blue
// one behind it, exact depth shows the blue surface in front and flat depth the red.
TEST_F(RenderTest, FlatDepthDrawsTouchingSpheresAsExactDepthDoes) {
    OrbitCamera camera;
    camera.frameBox({10, 10, 10}, float(kWidth) / kHeight);
    std::vector<ParticleInstance> heap;
    for (int k = 0; k < 75; ++k)
        heap.push_back({3.0f + float(k % 5), 0.5f + float(k / 25), 3.0f + float((k / 5) % 5), 0.5f, float(k % 3)});
    heap.push_back({5.0f, 4.0f, 5.0f, 1.0f, 2.0f});
    RenderStyle exact = plainStyle(), flat = plainStyle();
    flat.exactDepth = false;
    const Image a = draw(heap, camera, exact), b = draw(heap, camera, flat);
    size_t drawn = 0, differ = 0;
    const int bg[3] = {int(std::lround(exact.background[0] * 255)), int(std::lround(exact.background[1] * 255)),
                       int(std::lround(exact.background[2] * 255))};
    for (size_t p = 0; p < a.rgba.size(); p += 4) {
        const bool background = a.rgba[p] == bg[0] && a.rgba[p + 1] == bg[1] && a.rgba[p + 2] == bg[2];
        drawn += background ? 0 : 1;
        int most = 0;
        for (int c = 0; c < 3; ++c)
            most = std::max(most, std::abs(int(a.rgba[p + size_t(c)]) - int(b.rgba[p + size_t(c)])));
        differ += most > 8 ? 1 : 0;
    }
    EXPECT_GT(drawn, size_t(kWidth * kHeight / 40)) << "the heap covers a part of the frame";
    EXPECT_LT(double(differ), 0.01 * double(drawn)) << differ << " of " << drawn << " drawn pixels differ";

    const glm::vec3 toCamera = glm::normalize(camera.eye() - camera.target);
    const glm::vec3 side = glm::normalize(glm::cross(toCamera, glm::vec3(0, 0, 1)));
    // Red (radius 1) 2.1 in front of blue's centre (radius 3): the spheres intersect. Red's nearest point
    // (3.1 in front) lies before blue's (3.0), so flat depth shows red wherever red is drawn; 0.7 off the
    // line of centres blue's surface (2.92 in front) lies before red's (2.1 + 0.71), so exact depth shows blue.
    const ParticleInstance red{camera.target.x + 2.1f * toCamera.x, camera.target.y + 2.1f * toCamera.y,
                               camera.target.z + 2.1f * toCamera.z, 1.0f, 0.0f};
    const ParticleInstance blue{camera.target.x, camera.target.y, camera.target.z, 3.0f, 2.0f};
    const glm::vec2 probe = projectToPixel(camera, camera.target + 2.1f * toCamera + 0.7f * side, kWidth, kHeight);
    const Pixel e = at(draw({red, blue}, camera, exact), probe), f = at(draw({red, blue}, camera, flat), probe);
    EXPECT_GT(e.b, e.r + 30) << "exact depth: blue's surface is in front";
    EXPECT_GT(f.r, f.b + 30) << "flat depth: the nearer sphere is drawn whole";
}

TEST_F(RenderTest, SpeedModeMapsTheKeyRangeOntoTheColormapEnds) {
    OrbitCamera camera;
    camera.frameBox({10, 10, 10}, float(kWidth) / kHeight);
    RenderStyle style = plainStyle();
    style.mode = ColorMode::Speed;
    style.keyMin = 0;
    style.keyMax = 2;
    const std::vector<ParticleInstance> particles = {{3, 5, 5, 1.0f, 0.0f}, {7, 5, 5, 1.0f, 5.0f}};
    const Image img = draw(particles, camera, style);
    const Pixel slow = at(img, projectToPixel(camera, {3, 5, 5}, kWidth, kHeight));
    const Pixel fast = at(img, projectToPixel(camera, {7, 5, 5}, kWidth, kHeight));
    EXPECT_GT(slow.b, slow.g);  // viridis starts dark purple
    EXPECT_GT(fast.r + fast.g, 2 * fast.b + 100);  // and ends bright yellow (key above the range is clamped)
}
