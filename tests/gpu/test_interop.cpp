// A frame drawn through CUDA-GL interop equals the frame drawn from a CPU upload of the same state,
// on the EGL device that drives the CUDA device.
#include <cstdlib>

#include "egl_headless_context.h"
#include "gl_buffer_interop.h"
#include "gpu_fixture.h"
#include "image_io.h"
#include "initial_conditions.h"
#include "offscreen_target.h"
#include "particle_renderer.h"
#include "scene_io.h"
#include "scene_drawing.h"
#include "simulation.h"

using namespace corebox;

namespace {

Image drawFrame(ParticleRenderer& renderer, const Scene& scene, ColorMode mode) {
    OffscreenTarget target(480, 320);
    OrbitCamera camera;
    const std::array<float, 3> box{float(scene.box.size[0]), float(scene.box.size[1]), float(scene.box.size[2])};
    camera.frameBox({box[0], box[1], box[2]}, 480.0f / 320.0f);
    target.bind();
    renderer.render(camera, box, renderStyleFor(scene, mode), 480, 320);
    Image img{480, 320, {}};
    target.readPixels(img.rgba);
    return img;
}

}  // namespace

TEST(CudaInterop, InteropFrameEqualsTheCpuUploadFrame) {
    COREBOX_REQUIRE_GPU();
    std::unique_ptr<EglHeadlessContext> context;
    try {
        context = std::make_unique<EglHeadlessContext>(HeadlessContextOptions{0, false});
    } catch (const PlatformError& e) {
        FAIL() << "a GPU is present but no EGL device drives it: " << e.what();
    }
    const Scene scene = loadScene(std::string(COREBOX_SOURCE_DIR) + "/assets/polydisperse.toml");
    Simulation sim(scene, makeCudaBackend(CudaBackendOptions{Precision::Fp64, 0}), makeInitialState(scene));
    for (int s = 0; s < 10; ++s) sim.step();
    for (ColorMode mode : {ColorMode::Species, ColorMode::Speed}) {
        ParticleRenderer renderer;
        renderer.reserve(size_t(scene.particleCount()));
        CudaGlInterop interop(renderer.instanceBuffer(), 0);
        {
            const CudaGlInterop::Mapping mapping(interop);
            sim.backend().writeInstances(InstanceTarget{InstanceTarget::Memory::Device, mapping.instances(), mode});
        }
        renderer.setInstanceCount(size_t(scene.particleCount()));
        const Image viaInterop = drawFrame(renderer, scene, mode);
        std::vector<ParticleInstance> instances;
        buildInstances(sim.state(), scene, mode, instances);
        renderer.upload(instances.data(), instances.size());
        const Image viaUpload = drawFrame(renderer, scene, mode);
        size_t differing = 0;
        int worst = 0;
        for (size_t k = 0; k < viaUpload.rgba.size(); ++k) {
            const int d = std::abs(int(viaUpload.rgba[k]) - int(viaInterop.rgba[k]));
            differing += d != 0;
            worst = std::max(worst, d);
        }
        RecordProperty(mode == ColorMode::Species ? "species_differing_bytes" : "speed_differing_bytes", std::to_string(differing));
        EXPECT_EQ(differing, 0u) << "worst channel difference " << worst;
        if (const char* dir = std::getenv("COREBOX_GPU_FRAMES")) {
            writePng(std::string(dir) + (mode == ColorMode::Species ? "/interop_species.png" : "/interop_speed.png"), viaInterop);
        }
    }
}

// With two GPUs the render GPU's mapped buffer receives every slice (the gather before the fill): the
// frame equals the one-GPU frame of the same run.
TEST(CudaInterop, TwoGpusDrawTheOneGpuFrame) {
    COREBOX_REQUIRE_GPUS(2);
    EglHeadlessContext context(HeadlessContextOptions{0, false});
    const Scene scene = loadScene(std::string(COREBOX_SOURCE_DIR) + "/assets/polydisperse.toml");
    std::vector<Image> frames;
    for (int gpus : {1, 2}) {
        CudaBackendOptions options;
        options.gpus = gpus;
        Simulation sim(scene, makeCudaBackend(options), makeInitialState(scene));
        for (int s = 0; s < 10; ++s) sim.step();
        ParticleRenderer renderer;
        renderer.reserve(size_t(scene.particleCount()));
        CudaGlInterop interop(renderer.instanceBuffer(), 0);
        {
            const CudaGlInterop::Mapping mapping(interop);
            sim.backend().writeInstances(InstanceTarget{InstanceTarget::Memory::Device, mapping.instances(), ColorMode::Species});
        }
        renderer.setInstanceCount(size_t(scene.particleCount()));
        frames.push_back(drawFrame(renderer, scene, ColorMode::Species));
    }
    size_t differing = 0;
    for (size_t k = 0; k < frames[0].rgba.size(); ++k) differing += frames[0].rgba[k] != frames[1].rgba[k];
    RecordProperty("differing_bytes", std::to_string(differing));
    EXPECT_EQ(differing, 0u);
}
