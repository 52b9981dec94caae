// The smallest corebox program: a box, ten balls, gravity, one simulated second.
#include <corebox/corebox.h>

#include <cstdio>

int main() {
    try {
        corebox::WorldDef def;  // a 30 x 60 x 30 box, g = 9.81 down y, restitution 0.5, CPU, fp64
        corebox::World world(def);
        for (int i = 0; i < 10; ++i) {
            const corebox::Vec3d at{5.0 + 2.0 * i, 20.0 + 3.0 * i, 15.0};
            if (!world.addParticle({0, at, {0, 0, 0}})) return 1;
        }
        for (int frame = 0; frame < 60; ++frame) {
            world.advance(1.0 / 60.0);  // 4 fixed substeps of 1/240 per frame
        }
        for (size_t k = 0; k < world.particleCount(); ++k) {
            const corebox::Vec3d x = world.positions()[k];
            std::printf("ball %llu at (%.3f, %.3f, %.3f)\n", (unsigned long long)world.ids()[k], x.x, x.y, x.z);
        }
        std::printf("t = %.3f, %zu contacts in the last frame\n", world.time(), world.contacts().size());
    } catch (const std::exception& e) {
        std::fprintf(stderr, "falling_balls: %s\n", e.what());
        return 1;
    }
    return 0;
}
