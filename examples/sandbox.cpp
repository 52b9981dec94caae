// sandbox: corebox as a game programmer uses it. A window (or a headless EGL context) and the project's
// OpenGL renderer draw a corebox::World of balls falling in a 30 x 60 x 30 box; the mouse spawns and
// removes balls, SPACE fires a heavy ball, hard impacts flash, and the frame time is on screen.
//
//   sandbox [--balls 2000] [--backend cpu|cuda] [--precision fp32|fp64] [--frames F] [--headless]
//           [--scripted | --script FILE] [--screenshot FILE.png] [--stats FILE.json]   (--help: all)
//
// What it shows of the library (include/corebox/world.h):
// - a World from WorldDef's defaults but for a game's solver budget (kGameImpactRounds,
//   kGameContactSweeps, kGameContactListings), a second species added with addSpecies (mass 20, radius 1), balls added
//   with addParticles and each PlacementResult checked (overlaps are refused, never shifted), removeParticle after
//   queryRadius, applyImpulse;
// - the game loop: world.advance(1/60) once per rendered frame, spent in substeps of 1/240, on a worker
//   thread while the main thread draws the frame before (pipelined frames; --sequential: step, then draw;
//   --pace 60: frames start on a 60 Hz grid, as a display's vertical sync paces them);
// - drawing from the public spans positions(), speciesIndices(), ids(): nothing of the backend;
// - contacts(): impacts above an impulse threshold flash the balls they touch.
// Simulation code sees <corebox/corebox.h> only; the rest is the renderer (src/render) and the
// window and headless context (src/platform), which the corebox tree builds but does not install.
#include <corebox/corebox.h>

#include <epoxy/gl.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <glm/glm.hpp>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <unordered_map>
#include <vector>

#include "egl_headless_context.h"
#include "frame_worker.h"
#include "glfw_window.h"
#include "image_io.h"
#include "offscreen_target.h"
#include "orbit_camera.h"
#include "particle_renderer.h"
#include "render_style.h"
#include "sandbox_script.h"
#include "sandbox_stats.h"

namespace {

using corebox::ParticleId;
using corebox::Vec3d;
using Clock = std::chrono::steady_clock;

// Fixed step: every rendered frame advances the world by exactly kFramePeriod of simulated time
// (world.advance(1/60): 4 substeps of WorldDef::substep = 1/240), whatever the wall time of the frame.
// A machine that cannot keep 60 frames/s shows the simulation in slow motion instead of taking longer
// steps or dropping time, so a session is the same on every machine and every scripted run repeats.
constexpr double kFramePeriod = 1.0 / 60.0;
constexpr double kFlashSeconds = 0.2;    // simulated time a flash lasts
constexpr int kFlashLevels = 4;          // palette steps of a flash fading back to the species colour
constexpr double kFireSpeed = 40.0;      // heavy ball's launch speed [sigma / tau]
constexpr double kRemoveRadius = 2.0;    // right click removes the balls within this of the picked point
constexpr int kSkippedFrames = 10;       // --stats leaves out the first frames (start-up, first uploads)
constexpr double kBallRadius = 0.5;      // species 0: WorldDef's default ball
constexpr double kLatticeSpacing = 1.2;  // start lattice: a diameter and a gap
constexpr int64_t kMaxBalls = 2000000;
// The solver's budget, as a game sets its solver iterations (WorldDef::impactRounds, contactSweeps,
// contactListings): 16 impact rounds, 8 contact sweeps a listing and 2 listings a substep instead of
// corebox's 64, 16 and 32. What a capped step leaves goes to the contact solver, which stops it
// (restitution 0) rather than bounce it, or to the next step's contact solver: a dense landing bounces a
// little less and its overlaps last a step or two longer; energy is never gained. With it the scripted
// session holds 60 frames a second at 10^5 balls on an H200 and at 2,000 on a 2-core CPU, where
// corebox's own caps miss frames of the landing; the piles end as sound (docs/library.md, "The
// sandbox's frame times", has the figures).
constexpr int kGameImpactRounds = 16;
constexpr int kGameContactSweeps = 8;
constexpr int kGameContactListings = 2;

volatile std::sig_atomic_t g_interrupted = 0;
void onSignal(int) { g_interrupted = 1; }

double msSince(Clock::time_point t) { return 1e3 * std::chrono::duration<double>(Clock::now() - t).count(); }

// ---- vectors ---------------------------------------------------------------------------------------

Vec3d operator+(Vec3d a, Vec3d b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
Vec3d operator-(Vec3d a, Vec3d b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
Vec3d operator*(double s, Vec3d a) { return {s * a.x, s * a.y, s * a.z}; }
double dot(Vec3d a, Vec3d b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
double length(Vec3d a) { return std::sqrt(dot(a, a)); }
Vec3d normalised(Vec3d a) { return (1.0 / length(a)) * a; }

// ---- options ---------------------------------------------------------------------------------------

struct UsageError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// --depth: RenderStyle::exactDepth, or the renderer's choice (flat on a software rasteriser).
enum class SphereDepth { Auto, Exact, Flat };

struct Options {
    corebox::BackendKind backend = corebox::BackendKind::Cpu;
    corebox::Precision precision = corebox::Precision::Fp64;
    int64_t balls = 2000;
    int64_t frames = 0;  // 0: until the window closes (headless: 300)
    int threads = 0;  // 0: worldThreads() picks
    int contactSweeps = kGameContactSweeps;  // WorldDef::contactSweeps; 0: corebox's own
    int impactRounds = kGameImpactRounds;    // WorldDef::impactRounds; 0: corebox's own
    int contactListings = kGameContactListings;  // WorldDef::contactListings; 0: corebox's own
    bool headless = false;
    bool softwareGl = false;
    bool vsync = true;
    bool pipelined = true;
    int paceHz = 0;  // --pace: frames start on a grid of 1/paceHz, as a display's vertical sync paces them; 0: no wait
    int samples = corebox::GlfwWindow::kAutoSamples;  // multisampling; kAutoSamples: 4 on a GPU, 0 on software GL
    SphereDepth depth = SphereDepth::Auto;            // --depth
    bool scripted = false;
    std::string scriptPath, screenshotPath, statsPath;
    int width = 1280, height = 720;
    double flashImpulse = 5.0;
    double heavyRadius = 1.0;  // the heavy ball's radius [sigma]
    bool flashes = true;  // false: the world records no impacts (WorldDef::recordContacts), nothing flashes
    std::string commandLine;
};

const char* const kUsage =
    "usage: sandbox [options]\n"
    "  --balls N              balls on the start lattice (default 2000)\n"
    "  --backend cpu|cuda     where the World runs (default cpu)\n"
    "  --precision fp32|fp64  the World's precision (default fp64)\n"
    "  --threads N            the CPU world's threads (default 0: every hardware thread, but one when frames are\n"
    "                         pipelined: the main thread draws on it)\n"
    "  --contact-sweeps N     the contact solver's sweeps per listing (default 8; 0: corebox's own, 16)\n"
    "  --impact-rounds N      cap on the impact rounds per substep (default 16; 0: corebox's own, 64)\n"
    "  --contact-listings N   cap on the contact solver's listings per substep (default 2; 0: corebox's own, 32)\n"
    "  --frames F             exit after F frames (default: until the window closes; headless 300)\n"
    "  --headless             no window: an EGL context rendering offscreen (same loop)\n"
    "  --software-gl          headless on Mesa's software renderer even where a GPU is present\n"
    "  --size WxH             window or frame size in pixels (default 1280x720)\n"
    "  --no-vsync             do not wait for the display between frames\n"
    "  --pace HZ              start frames on a 1/HZ grid, as a display's vertical sync does where there is\n"
    "                         none (Xvfb, EGL): a frame presented after its period missed a refresh and the next\n"
    "                         starts at the refresh after it; the display's own sync is then off (default 0: no wait)\n"
    "  --samples N|auto       multisampling of the frame (default auto: 4 on a GPU, none on a software renderer)\n"
    "  --depth exact|flat|auto  spheres' depth: each fragment's own, or the sphere's nearest point's (touching\n"
    "                         balls look the same; a software renderer draws a third faster) (default auto:\n"
    "                         flat on a software renderer)\n"
    "  --sequential           step the world, then draw (default: the next frame's step runs while one is drawn)\n"
    "  --scripted             play the built-in session: spawn clicks, a shot at frame 30, removals\n"
    "  --script FILE          play FILE: lines 'FRAME click|hold|remove|fire|orbit|zoom|screenshot|quit ...'\n"
    "  --screenshot FILE.png  save the last frame\n"
    "  --stats FILE.json      frame-time statistics (after the first 10 frames) and the run's setup\n"
    "  --flash-impulse J      impacts above this impulse flash their balls (default 5)\n"
    "  --heavy-radius R       the heavy ball's radius (default 1; the balls' is 0.5)\n"
    "  --no-flashes           the world records no impacts (WorldDef::recordContacts = false): nothing flashes\n"
    "  --help                 this text\n"
    "mouse: left click or hold spawns balls, right click removes balls; SPACE fires a heavy ball;\n"
    "arrows orbit the camera, PageUp/PageDown zoom; ESC quits.\n";

std::string shellQuoted(const std::string& s) {
    if (!s.empty() && s.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789-_./=:,+@") ==
                          std::string::npos)
        return s;
    std::string out = "'";
    for (const char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return out + "'";
}

// A whole number in [lowest, highest], checked before any narrowing to int.
int64_t parseInteger(const std::string& flag, const std::string& text, int64_t lowest, int64_t highest = INT64_MAX) {
    size_t used = 0;
    long long v = 0;
    try {
        v = std::stoll(text, &used);
    } catch (const std::exception&) {
        used = 0;
    }
    if (used == 0 || used != text.size() || v < lowest)
        throw UsageError(flag + ": '" + text + "' is not a whole number >= " + std::to_string(lowest));
    if (v > highest) throw UsageError(flag + ": at most " + std::to_string(highest));
    return v;
}

Options parseOptions(int argc, char** argv) {
    Options o;
    o.commandLine = shellQuoted(argv[0]);
    for (int i = 1; i < argc; ++i) o.commandLine += " " + shellQuoted(argv[i]);
    bool framesGiven = false;
    for (int i = 1; i < argc; ++i) {
        const std::string flag = argv[i];
        auto value = [&]() -> std::string {
            if (i + 1 >= argc) throw UsageError(flag + " needs a value");
            return argv[++i];
        };
        if (flag == "--help" || flag == "-h") {
            std::fputs(kUsage, stdout);
            std::exit(0);
        } else if (flag == "--balls") {
            o.balls = parseInteger(flag, value(), 0);
            // The floor widens with the count (worldDef); beyond this the start lattice alone takes minutes.
            if (o.balls > kMaxBalls) throw UsageError("--balls " + std::to_string(o.balls) + ": at most " + std::to_string(kMaxBalls));
        } else if (flag == "--backend") {
            const std::string v = value();
            if (v == "cpu")
                o.backend = corebox::BackendKind::Cpu;
            else if (v == "cuda")
                o.backend = corebox::BackendKind::Cuda;
            else
                throw UsageError("--backend: '" + v + "' is not cpu or cuda");
        } else if (flag == "--precision") {
            const std::string v = value();
            if (v == "fp32")
                o.precision = corebox::Precision::Fp32;
            else if (v == "fp64")
                o.precision = corebox::Precision::Fp64;
            else
                throw UsageError("--precision: '" + v + "' is not fp32 or fp64");
        } else if (flag == "--threads") {
            o.threads = int(parseInteger(flag, value(), 0, 4096));
        } else if (flag == "--contact-sweeps") {
            o.contactSweeps = int(parseInteger(flag, value(), 0, 1024));
        } else if (flag == "--impact-rounds") {
            o.impactRounds = int(parseInteger(flag, value(), 0, 4096));
        } else if (flag == "--contact-listings") {
            o.contactListings = int(parseInteger(flag, value(), 0, corebox::WorldDef::kMaxContactListings));
        } else if (flag == "--frames") {
            o.frames = parseInteger(flag, value(), 1);
            framesGiven = true;
        } else if (flag == "--headless") {
            o.headless = true;
        } else if (flag == "--software-gl") {
            o.softwareGl = true;
        } else if (flag == "--depth") {
            const std::string v = value();
            if (v == "exact")
                o.depth = SphereDepth::Exact;
            else if (v == "flat")
                o.depth = SphereDepth::Flat;
            else if (v == "auto")
                o.depth = SphereDepth::Auto;
            else
                throw UsageError("--depth: '" + v + "' is not exact, flat or auto");
        } else if (flag == "--pace") {
            o.paceHz = int(parseInteger(flag, value(), 0, 1000));
        } else if (flag == "--no-vsync") {
            o.vsync = false;
        } else if (flag == "--samples") {
            const std::string v = value();
            o.samples = v == "auto" ? corebox::GlfwWindow::kAutoSamples : int(parseInteger(flag, v, 0, 16));
        } else if (flag == "--sequential") {
            o.pipelined = false;
        } else if (flag == "--size") {
            const std::string v = value();
            const size_t x = v.find('x');
            if (x == std::string::npos) throw UsageError("--size: '" + v + "' is not WIDTHxHEIGHT");
            o.width = int(parseInteger("--size width", v.substr(0, x), 16, 8192));
            o.height = int(parseInteger("--size height", v.substr(x + 1), 16, 8192));
        } else if (flag == "--scripted") {
            o.scripted = true;
        } else if (flag == "--script") {
            o.scriptPath = value();
        } else if (flag == "--screenshot") {
            o.screenshotPath = value();
        } else if (flag == "--stats") {
            o.statsPath = value();
        } else if (flag == "--heavy-radius") {
            const std::string v = value();
            char* end = nullptr;
            o.heavyRadius = std::strtod(v.c_str(), &end);
            if (end == v.c_str() || *end != '\0' || !(o.heavyRadius >= 0.1 && o.heavyRadius <= 5))
                throw UsageError("--heavy-radius: '" + v + "' is not a radius from 0.1 to 5");
        } else if (flag == "--no-flashes") {
            o.flashes = false;
        } else if (flag == "--flash-impulse") {
            const std::string v = value();
            char* end = nullptr;
            o.flashImpulse = std::strtod(v.c_str(), &end);
            if (end == v.c_str() || *end != '\0' || !(o.flashImpulse >= 0) || !std::isfinite(o.flashImpulse))
                throw UsageError("--flash-impulse: '" + v + "' is not a number >= 0");
        } else {
            throw UsageError("unknown option '" + flag + "'");
        }
    }
    if (o.scripted && !o.scriptPath.empty()) throw UsageError("--scripted and --script: choose one");
    if (o.softwareGl && !o.headless) throw UsageError("--software-gl is for --headless runs");
    if (o.headless && !framesGiven) o.frames = 300;
    return o;
}

// ---- between the World's frame and the renderer's --------------------------------------------------

// The World stands on y (gravity -y) while the renderer's orbit camera turns about z. Drawing rotates
// the world by 90 degrees about x (and shifts it back into the positive octant): the world's y becomes
// the screen's up, and nothing is mirrored. Picking maps back.
struct ViewMap {
    Vec3d box;
    glm::vec3 toRender(const Vec3d& p) const { return {float(p.x), float(box.z - p.z), float(p.y)}; }
    Vec3d toWorld(const glm::vec3& r) const { return {r.x, r.z, box.z - r.y}; }
    Vec3d directionToWorld(const glm::vec3& d) const { return {d.x, d.z, -d.y}; }
    std::array<float, 3> renderBox() const { return {float(box.x), float(box.z), float(box.y)}; }
};

// A ray from the camera through a point of the screen, in world coordinates, and the camera's forward.
struct Ray {
    Vec3d origin, direction, forward;
};

Ray cursorRay(const corebox::OrbitCamera& camera, const ViewMap& map, double u, double v, float aspect) {
    const glm::mat4 inverse = glm::inverse(camera.projection(aspect) * camera.view());
    const glm::vec2 ndc(float(2.0 * u - 1.0), float(1.0 - 2.0 * v));
    const glm::vec4 nearPoint = inverse * glm::vec4(ndc, -1.0f, 1.0f);
    const glm::vec4 farPoint = inverse * glm::vec4(ndc, 1.0f, 1.0f);
    const glm::vec3 a = glm::vec3(nearPoint) / nearPoint.w, b = glm::vec3(farPoint) / farPoint.w;
    Ray ray;
    ray.origin = map.toWorld(camera.eye());
    ray.direction = normalised(map.directionToWorld(b - a));
    ray.forward = normalised(map.directionToWorld(camera.target - camera.eye()));
    return ray;
}

// ---- the game: a World, its heavy balls, its flashes -----------------------------------------------

class Sandbox {
public:
    explicit Sandbox(const Options& options)
        : m_world(worldDef(options)),
          m_box(m_world.boxSize()),
          m_flashImpulse(options.flashImpulse),
          m_worldOnGpu(options.backend == corebox::BackendKind::Cuda) {
        corebox::ParticleSpecies heavy;
        heavy.name = "heavy";
        heavy.mass = 20.0;
        heavy.radius = options.heavyRadius;
        heavy.color = {0.25f, 0.5f, 0.95f};
        m_heavy = m_world.addSpecies(heavy);
        for (int s = 0; s < m_world.speciesCount(); ++s) m_species.push_back(m_world.species(s));
        placeLattice(options.balls);
    }

    corebox::World& world() { return m_world; }
    const Vec3d& box() const { return m_box; }

    struct Outcome {
        int64_t done = 0, refused = 0;
        std::optional<Vec3d> at;
    };

    // A left click: a 2 x 2 x 2 cube of balls at rest around the point where the cursor's ray meets the
    // vertical plane through the box centre that faces the camera. A held button repeats it as a stream:
    // each cube thrown down and scattered a little sideways, so that it mostly misses the one before.
    // Overlapping placements are refused by the World; they are only counted.
    Outcome spawn(const Ray& ray, bool repeat) {
        Outcome out;
        out.at = pickPlane(ray);
        if (!out.at) return out;
        Vec3d velocity{0, 0, 0};
        if (repeat) {
            const double m = 2 * kBallRadius + 0.1;
            out.at = Vec3d{std::clamp(out.at->x + 2.0 * random(), m, m_box.x - m), out.at->y,
                           std::clamp(out.at->z + 2.0 * random(), m, m_box.z - m)};
            velocity = {0, -6, 0};
        }
        std::vector<corebox::ParticleDef> cube;
        const double h = 0.55;  // half the spacing of 1.1: neighbours do not touch
        for (int k = 0; k < 8; ++k) {
            const Vec3d offset{k & 1 ? h : -h, k & 2 ? h : -h, k & 4 ? h : -h};
            cube.push_back(corebox::ParticleDef{0, *out.at + offset, velocity});
        }
        for (const corebox::PlacementResult& p : m_world.addParticles(cube)) ++(p ? out.done : out.refused);
        if (out.done > 0) ++m_setEdits;
        spawned += out.done;
        spawnRefused += out.refused;
        return out;
    }

    // A right click: the balls within kRemoveRadius of the first ball under the cursor (or, when the
    // ray hits none, of the point on the pick plane).
    Outcome remove(const Ray& ray) {
        Outcome out;
        out.at = firstBallHit(ray);
        if (!out.at) out.at = pickPlane(ray);
        if (!out.at) return out;
        for (const ParticleId id : m_world.queryRadius(*out.at, kRemoveRadius)) {
            m_world.removeParticle(id);
            ++out.done;
        }
        if (out.done > 0) ++m_setEdits;
        removed += out.done;
        return out;
    }

    // SPACE: a heavy ball on the line from the camera to the box centre, placed where that line enters
    // the box (or, when balls are in the way, the first free place further along), then sent toward the
    // centre with an impulse.
    Outcome fire(const Vec3d& eye) {
        Outcome out;
        const Vec3d centre = 0.5 * m_box;
        const Vec3d dir = normalised(centre - eye);
        const double margin = radius(m_heavy) + 0.01;
        // Where the ray enters the box shrunk by the heavy radius (slabs), and where it reaches the centre.
        double enter = 0.0;
        const double e[3] = {eye.x, eye.y, eye.z}, d[3] = {dir.x, dir.y, dir.z}, l[3] = {m_box.x, m_box.y, m_box.z};
        for (int a = 0; a < 3; ++a) {
            if (std::abs(d[a]) < 1e-12) continue;
            const double t0 = (margin - e[a]) / d[a], t1 = (l[a] - margin - e[a]) / d[a];
            enter = std::max(enter, std::min(t0, t1));
        }
        const double reach = length(centre - eye);
        for (double t = enter; t <= reach; t += 0.25) {
            const corebox::PlacementResult p = m_world.addParticle({m_heavy, eye + t * dir, {0, 0, 0}});
            if (!p) continue;
            ++m_setEdits;
            m_world.applyImpulse(p.id, (m_world.species(m_heavy).mass * kFireSpeed) * dir);
            out.at = eye + t * dir;
            out.done = 1;
            ++fired;
            return out;
        }
        out.refused = 1;
        ++fireRefused;
        return out;
    }

    // How still and how sound the balls are (for the --stats file, at the end of a run): the kinetic
    // energy per ball, and the deepest overlap of two cores or of a core and a wall, as a fraction of
    // the contact distance (the ball's diameter at a wall), through the public queries only.
    struct Soundness {
        double kineticPerBall = 0, maxOverlap = 0;
    };
    Soundness soundness() {
        Soundness out;
        const corebox::Span<Vec3d> x = m_world.positions();
        const corebox::Span<ParticleId> ids = m_world.ids();
        const corebox::Span<int32_t> species = m_world.speciesIndices();
        if (x.size == 0) return out;
        out.kineticPerBall = m_world.energy().kinetic / double(x.size);
        double largest = 0;
        for (const corebox::ParticleSpecies& sp : m_species) largest = std::max(largest, sp.radius);
        const double box[3] = {m_box.x, m_box.y, m_box.z};
        for (size_t k = 0; k < x.size; ++k) {
            const double r = radius(species[k]);
            const double at[3] = {x[k].x, x[k].y, x[k].z};
            for (int a = 0; a < 3; ++a)
                out.maxOverlap = std::max({out.maxOverlap, (r - at[a]) / (2 * r), (at[a] + r - box[a]) / (2 * r)});
            for (const ParticleId other : m_world.queryRadius(x[k], r + largest)) {
                if (other <= ids[k]) continue;  // each pair once
                const Vec3d y = m_world.position(other);
                const double d = r + radius(m_world.speciesOf(other));
                const double gap = std::sqrt((x[k].x - y.x) * (x[k].x - y.x) + (x[k].y - y.y) * (x[k].y - y.y) +
                                             (x[k].z - y.z) * (x[k].z - y.z));
                out.maxOverlap = std::max(out.maxOverlap, (d - gap) / d);
            }
        }
        return out;
    }

    // One rendered frame of simulation (on the frame worker when frames are pipelined).
    corebox::StepInfo advanceFrame() { return m_world.advance(kFramePeriod); }

    // The flashes of the last frame's hard impacts.
    void noteImpacts() {
        const double until = m_world.time() + kFlashSeconds;
        auto flash = [&](ParticleId id) {
            if (id >= m_flashUntil.size()) m_flashUntil.resize(size_t(id) + 1, kNoFlash);
            m_flashUntil[size_t(id)] = until;
        };
        for (const corebox::Contact& c : m_world.contacts()) {
            if (std::abs(c.impulse) < m_flashImpulse) continue;
            flash(c.a);
            if (c.kind == corebox::ContactKind::Pair) flash(c.b);
            ++flashes;
        }
    }

    // What a frame draws, copied out of the World's public spans while it is not stepping, so that the
    // next frame's step can start before the drawing is built from it (pipelined frames). Before, the
    // instances, the legend's counts and the HUD were built from the spans while the world waited: on an
    // H200 at 10^5 balls (fp32, host probes, one call each) the GPU stood idle 3.5 ms between a frame's
    // last step and the next frame's first, and 2.3 to 3.0 ms after; the frames took 8.9 ms on average
    // instead of 10.1 to 10.3 (calls apart), the same state hash.
    // The copy is on the frame's critical path (the GPU idles until the next step is posted), so it takes
    // the fewest bytes, on every core: positions straight into the renderer's coordinates (floats),
    // species and ids only after the sandbox added or removed balls. An H200 at 10^5 balls (fp32, host
    // probes): 0.51 to 0.55 ms a landing frame when it copied positions as doubles and every species and
    // id, 0.44 with the fewest bytes on one thread, 0.08 to 0.14 on every core. Tried and not kept:
    // noteImpacts on every core (its contacts read twice, the flash times written atomically): 0.24 to
    // 0.30 ms a landing frame against 0.27 to 0.41 on one thread, within the calls' spread.
    struct Drawn {
        std::vector<glm::vec3> x;  // render coordinates (ViewMap::toRender)
        std::vector<int32_t> species;
        std::vector<ParticleId> ids;
        double time = 0;
        int64_t setEdits = -1;  // Sandbox::m_setEdits when species and ids were copied
    };
    void copyDrawn(const ViewMap& map, Drawn& out) {
        const corebox::Span<Vec3d> x = m_world.positions();
        out.x.resize(x.size);
        const int64_t n = int64_t(x.size);
        // Not beside a CPU world: its OpenMP team would spin on after the loop on the cores the step needs.
        const bool everyCore = n >= 16384 && m_worldOnGpu;
#pragma omp parallel for schedule(static) if (everyCore)
        for (int64_t k = 0; k < n; ++k) out.x[size_t(k)] = map.toRender(x[size_t(k)]);
        if (out.setEdits != m_setEdits) {
            const corebox::Span<int32_t> species = m_world.speciesIndices();
            const corebox::Span<ParticleId> ids = m_world.ids();
            out.species.assign(species.begin(), species.end());
            out.ids.assign(ids.begin(), ids.end());
            out.setEdits = m_setEdits;
        }
        out.time = m_world.time();
    }

    // The renderer's particle view: centre, radius and a colour key per ball. The key is the species'
    // palette entry, or one of kFlashLevels entries fading from white.
    void buildInstances(const Drawn& drawn, std::vector<corebox::ParticleInstance>& out) const {
        const int nSpecies = int(m_species.size());
        out.resize(drawn.x.size());
        for (size_t k = 0; k < drawn.x.size(); ++k) {
            const int s = drawn.species[k];
            float key = float(s);
            const ParticleId id = drawn.ids[k];
            const double until = id < m_flashUntil.size() ? m_flashUntil[size_t(id)] : kNoFlash;
            if (until > drawn.time) {
                const double left = (until - drawn.time) / kFlashSeconds;  // 1 at the impact, 0 at the end
                const int level = std::clamp(int((1.0 - left) * kFlashLevels), 0, kFlashLevels - 1);
                key = float(nSpecies + s * kFlashLevels + level);
            }
            const glm::vec3& r = drawn.x[k];
            out[k] = corebox::ParticleInstance{r.x, r.y, r.z, float(radius(s)), key};
        }
    }

    // Species colours, then each species' flash levels; the legend lists the species with their counts,
    // then the HUD's lines (text with an invisible swatch: the renderer's legend is its text overlay).
    // From the species as made (the sandbox adds none later), not from the World, which may be stepping.
    corebox::RenderStyle style(const Drawn& drawn, const std::vector<std::string>& hudLines) const {
        corebox::RenderStyle style;
        style.mode = corebox::ColorMode::Species;
        const int nSpecies = int(m_species.size());
        std::vector<int64_t> counts(size_t(nSpecies), 0);
        for (const int32_t s : drawn.species) ++counts[size_t(s)];
        for (int s = 0; s < nSpecies; ++s) {
            const corebox::ParticleSpecies& sp = m_species[size_t(s)];
            style.palette.push_back(sp.color);
            style.speciesLegend.push_back({sp.name + "  " + std::to_string(counts[size_t(s)]), sp.color});
        }
        for (int s = 0; s < nSpecies; ++s) {
            const std::array<float, 3> c = m_species[size_t(s)].color;
            for (int level = 0; level < kFlashLevels; ++level) {
                const float white = 1.0f - float(level) / float(kFlashLevels);
                style.palette.push_back(
                    {c[0] + white * (1.0f - c[0]), c[1] + white * (1.0f - c[1]), c[2] + white * (1.0f - c[2])});
            }
        }
        for (const std::string& line : hudLines) style.speciesLegend.push_back({line, style.background});
        return style;
    }

    int64_t spawned = 0, spawnRefused = 0, removed = 0, fired = 0, fireRefused = 0, flashes = 0;
    int64_t ballsAtStart = 0;

private:
    // The CPU world's threads. Pipelined, the main thread draws (and on Mesa's software renderer its
    // rasteriser threads run) while the world steps: the world leaves it a core. A settled pile's step is
    // mostly its sequential contact sweeps, so a second world thread would mostly spin in OpenMP's barriers
    // on the core the renderer needs: on a 2-core machine, 2,000 balls on llvmpipe, 1 thread gave 72
    // frames a second and 2 gave 58 (the same state hash with either).
    static int worldThreads(const Options& o) {
        if (o.threads > 0 || !o.pipelined) return o.threads;
        return std::max(1, int(std::thread::hardware_concurrency()) - 1);
    }

    static corebox::WorldDef worldDef(const Options& o) {
        corebox::WorldDef def;  // box 30 x 60 x 30, g = -9.81 y, restitution 0.5, substep 1/240
        // More balls than the default box's upper half holds on the start lattice: a wider floor (the
        // height stays 60), so that 10^5 balls start in the upper half of a 92 x 60 x 92 box.
        const double layers = std::floor(0.5 * def.boxSize.y / kLatticeSpacing);
        const double across = std::ceil(std::sqrt(double(o.balls) / layers));
        def.boxSize.x = def.boxSize.z = std::max(def.boxSize.x, across * kLatticeSpacing + 2 * (kBallRadius + 0.1));
        def.backend = o.backend;
        def.precision = o.precision;
        def.threads = worldThreads(o);
        def.contactSweeps = o.contactSweeps;
        def.impactRounds = o.impactRounds;
        def.contactListings = o.contactListings;
        def.recordContacts = o.flashes;
        def.contactMinImpulse = o.flashImpulse;  // only the impacts that flash
        return def;
    }

    // The start: a square lattice filled layer by layer from the top of the box down, each ball nudged
    // a little sideways (a perfect lattice would land in perfect columns).
    void placeLattice(int64_t n) {
        const double margin = kBallRadius + 0.1;
        const int nx = int((m_box.x - 2 * margin) / kLatticeSpacing) + 1;
        const int nz = int((m_box.z - 2 * margin) / kLatticeSpacing) + 1;
        const int layers = int((m_box.y - 2 * margin) / kLatticeSpacing) + 1;
        const int64_t capacity = int64_t(nx) * nz * layers;
        if (n > capacity)
            throw UsageError("--balls " + std::to_string(n) + ": at most " + std::to_string(capacity) +
                             " fit on the start lattice");
        const double x0 = 0.5 * (m_box.x - (nx - 1) * kLatticeSpacing),
                     z0 = 0.5 * (m_box.z - (nz - 1) * kLatticeSpacing);
        auto jitter = [this]() { return 0.16 * random(); };  // +-0.08
        std::vector<corebox::ParticleDef> defs;
        defs.reserve(size_t(n));
        for (int64_t k = 0; k < n; ++k) {
            const int64_t layer = k / (int64_t(nx) * nz), inLayer = k % (int64_t(nx) * nz);
            const double x = x0 + double(inLayer % nx) * kLatticeSpacing + jitter();
            const double z = z0 + double(inLayer / nx) * kLatticeSpacing + jitter();
            const double y = m_box.y - margin - double(layer) * kLatticeSpacing;
            defs.push_back(corebox::ParticleDef{0, {x, y, z}, {0, 0, 0}});
        }
        const std::vector<corebox::PlacementResult> placed = m_world.addParticles(defs);
        for (size_t k = 0; k < placed.size(); ++k) {
            if (!placed[k])
                throw corebox::InputError("start lattice: ball " + std::to_string(k) + " refused: " + placed[k].reason);
        }
        ballsAtStart = int64_t(placed.size());
    }

    // In [-0.5, 0.5): xorshift, the same sequence on every machine (std:: distributions are not).
    double random() {
        m_seed ^= m_seed << 13;
        m_seed ^= m_seed >> 7;
        m_seed ^= m_seed << 17;
        return double(m_seed >> 11) / double(1ull << 53) - 0.5;
    }

    std::optional<Vec3d> pickPlane(const Ray& ray) const {
        Vec3d normal{ray.forward.x, 0.0, ray.forward.z};  // a vertical plane facing the camera
        if (length(normal) < 1e-6) normal = ray.forward;  // looking straight down: a horizontal one
        normal = normalised(normal);
        const Vec3d centre = 0.5 * m_box;
        const double denom = dot(ray.direction, normal);
        if (std::abs(denom) < 1e-9) return std::nullopt;
        const double t = dot(centre - ray.origin, normal) / denom;
        if (t < 0) return std::nullopt;
        const Vec3d p = ray.origin + t * ray.direction;
        const double m = 2 * kBallRadius + 0.1;  // the spawned cube stays inside
        return Vec3d{std::clamp(p.x, m, m_box.x - m), std::clamp(p.y, m, m_box.y - m), std::clamp(p.z, m, m_box.z - m)};
    }

    std::optional<Vec3d> firstBallHit(const Ray& ray) {
        const corebox::Span<Vec3d> x = m_world.positions();
        const corebox::Span<int32_t> species = m_world.speciesIndices();
        double best = INFINITY;
        std::optional<Vec3d> hit;
        for (size_t k = 0; k < x.size; ++k) {
            const Vec3d oc = ray.origin - x[k];
            const double r = radius(species[k]);
            const double b = dot(oc, ray.direction), c = dot(oc, oc) - r * r;
            const double disc = b * b - c;
            if (disc < 0) continue;
            const double t = -b - std::sqrt(disc);
            if (t > 0 && t < best) {
                best = t;
                hit = x[k];
            }
        }
        return hit;
    }

    corebox::World m_world;
    Vec3d m_box;
    double m_flashImpulse;
    int m_heavy = 1;
    std::vector<corebox::ParticleSpecies> m_species;  // as made: names, colours and radii
    double radius(int species) const { return m_species[size_t(species)].radius; }
    // The simulated time each ball's flash ends, by id (the World's ids count up from 0): a read a ball
    // a frame. A hash map cost the landing of 10^5 balls milliseconds a frame, its look-ups and the
    // clearing of ended flashes on the main thread between steps.
    std::vector<double> m_flashUntil;
    int64_t m_setEdits = 0;  // calls that added or removed balls (Drawn copies species and ids after one)
    bool m_worldOnGpu = false;
    static constexpr double kNoFlash = -1e300;
    uint64_t m_seed = 0x9E3779B97F4A7C15ull;
};

// ---- where frames go: a GLFW window, or an offscreen target on an EGL context ----------------------

class Frontend {
public:
    virtual ~Frontend() = default;
    virtual void drawableSize(int* width, int* height) = 0;
    // The frame's user input as commands (the script's vocabulary); `closed` when the window closed.
    virtual std::vector<sandbox::Command> poll(bool* closed) = 0;
    virtual void bindTarget() = 0;
    virtual corebox::Image readFrame(int width, int height) = 0;
    virtual void present() {}
    virtual void setTitle(const std::string&) {}
    virtual int samples() const = 0;  // multisampling of the frames drawn
};

class WindowFrontend : public Frontend {
public:
    explicit WindowFrontend(const Options& o) : m_window(o.width, o.height, "corebox sandbox", o.samples) {
        m_window.setVsync(o.vsync && o.paceHz == 0);  // --pace is the vertical sync: the display's would fight it
    }

    void drawableSize(int* width, int* height) override { m_window.framebufferSize(width, height); }

    std::vector<sandbox::Command> poll(bool* closed) override {
        glfwPollEvents();
        GLFWwindow* w = m_window.handle();
        *closed = m_window.shouldClose();
        std::vector<sandbox::Command> out;
        double cx = 0, cy = 0;
        int ww = 1, wh = 1;
        glfwGetCursorPos(w, &cx, &cy);
        glfwGetWindowSize(w, &ww, &wh);
        const double u = cx / std::max(ww, 1), v = cy / std::max(wh, 1);
        const bool inside = u >= 0 && u <= 1 && v >= 0 && v <= 1;
        auto command = [&](sandbox::CommandKind kind, double a = 0, double b = 0) {
            sandbox::Command c;
            c.kind = kind;
            c.u = a;
            c.v = b;
            out.push_back(c);
        };
        const bool left = glfwGetMouseButton(w, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS;
        const bool right = glfwGetMouseButton(w, GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS;
        const bool space = glfwGetKey(w, GLFW_KEY_SPACE) == GLFW_PRESS;
        m_leftHeldFrames = left ? m_leftHeldFrames + 1 : 0;
        if (left && inside && (m_leftHeldFrames - 1) % sandbox::kSpawnEveryFrames == 0) {
            command(sandbox::CommandKind::Spawn, u, v);
            out.back().repeat = m_leftHeldFrames > 1;
        }
        if (right && !m_right && inside) command(sandbox::CommandKind::Remove, u, v);
        if (space && !m_space) command(sandbox::CommandKind::Fire);
        m_right = right;
        m_space = space;
        const double turn = 0.03;
        if (glfwGetKey(w, GLFW_KEY_LEFT) == GLFW_PRESS) command(sandbox::CommandKind::Orbit, -turn, 0);
        if (glfwGetKey(w, GLFW_KEY_RIGHT) == GLFW_PRESS) command(sandbox::CommandKind::Orbit, turn, 0);
        if (glfwGetKey(w, GLFW_KEY_UP) == GLFW_PRESS) command(sandbox::CommandKind::Orbit, 0, turn);
        if (glfwGetKey(w, GLFW_KEY_DOWN) == GLFW_PRESS) command(sandbox::CommandKind::Orbit, 0, -turn);
        if (glfwGetKey(w, GLFW_KEY_PAGE_UP) == GLFW_PRESS) command(sandbox::CommandKind::Zoom, 0.98);
        if (glfwGetKey(w, GLFW_KEY_PAGE_DOWN) == GLFW_PRESS) command(sandbox::CommandKind::Zoom, 1.02);
        if (glfwGetKey(w, GLFW_KEY_ESCAPE) == GLFW_PRESS) command(sandbox::CommandKind::Quit);
        return out;
    }

    void bindTarget() override {
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
        glEnable(GL_MULTISAMPLE);
    }

    corebox::Image readFrame(int width, int height) override {
        corebox::Image img{width, height, std::vector<uint8_t>(size_t(width) * size_t(height) * 4)};
        glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
        glReadBuffer(GL_BACK);
        glPixelStorei(GL_PACK_ALIGNMENT, 1);
        glReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, img.rgba.data());
        corebox::flipRows(img.rgba, width, height);
        return img;
    }

    void present() override { glfwSwapBuffers(m_window.handle()); }
    void setTitle(const std::string& title) override { m_window.setTitle(title); }
    int samples() const override { return m_window.samples(); }

private:
    corebox::GlfwWindow m_window;
    int64_t m_leftHeldFrames = 0;
    bool m_right = false, m_space = false;
};

class HeadlessFrontend : public Frontend {
public:
    explicit HeadlessFrontend(const Options& o)
        : m_context(corebox::HeadlessContextOptions{-1, o.softwareGl}),
          m_samples(o.samples != corebox::GlfwWindow::kAutoSamples
                        ? o.samples
                        : corebox::GlfwWindow::autoSamples(reinterpret_cast<const char*>(glGetString(GL_RENDERER)))),
          m_target(o.width, o.height, m_samples) {}
    int samples() const override { return m_target.samples(); }

    void drawableSize(int* width, int* height) override {
        *width = m_target.width();
        *height = m_target.height();
    }
    std::vector<sandbox::Command> poll(bool* closed) override {
        *closed = false;
        return {};
    }
    void bindTarget() override { m_target.bind(); }
    corebox::Image readFrame(int width, int height) override {
        corebox::Image img{width, height, {}};
        m_target.readPixels(img.rgba);
        return img;
    }
    const std::string& description() const { return m_context.description(); }

private:
    corebox::EglHeadlessContext m_context;  // first: the target's GL objects need it
    int m_samples;                          // asked of the target: a pixel's samples (0 or 1: none)
    corebox::OffscreenTarget m_target;
};

// ---- the session -------------------------------------------------------------------------------------

std::string format(const char* fmt, double a, double b = 0, double c = 0, double d = 0) {
    char buf[256];
    std::snprintf(buf, sizeof buf, fmt, a, b, c, d);
    return buf;
}

std::string hex(uint64_t v) {
    char buf[24];
    std::snprintf(buf, sizeof buf, "0x%016llx", (unsigned long long)v);
    return buf;
}

const char* precisionName(corebox::Precision p) { return p == corebox::Precision::Fp32 ? "fp32" : "fp64"; }
const char* backendName(corebox::BackendKind b) { return b == corebox::BackendKind::Cuda ? "cuda" : "cpu"; }

// What the World reported over the run (the sum of every advance()'s StepInfo).
struct StepTotals {
    int64_t substeps = 0, pairCollisions = 0, wallCollisions = 0, roundCapHits = 0, contactListings = 0;
    double droppedTime = 0, overlapLeft = 0;
    void add(const corebox::StepInfo& i) {
        substeps += i.substeps;
        contactListings += i.contactListings;
        overlapLeft = std::max(overlapLeft, i.overlapLeft);
        pairCollisions += i.pairCollisions;
        wallCollisions += i.wallCollisions;
        roundCapHits += i.roundCapHits;
        droppedTime += i.droppedTime;
    }
};

void writeStats(const Options& o, Sandbox& game, const std::vector<sandbox::FrameSample>& samples,
                const StepTotals& steps, double wallSeconds, double measuredSeconds, const std::string& glRenderer,
                int frameSamples, bool exactDepth) {
    using sandbox::FrameSample;
    auto summary = [&](double FrameSample::*field) { return sandbox::summarise(sandbox::column(samples, kSkippedFrames, field)); };
    const sandbox::Summary frameSummary = summary(&FrameSample::frameMs);
    // A GPU: the World's CUDA device, or the GL renderer when it is hardware (not a software rasteriser).
    std::string gpu;
    if (o.backend == corebox::BackendKind::Cuda)
        gpu = game.world().backendName();
    else if (!corebox::GlfwWindow::isSoftwareRenderer(glRenderer))
        gpu = glRenderer;
    sandbox::JsonObject json;
    json.add("program", "sandbox")
        .add("command_line", o.commandLine)
        .add("backend", backendName(o.backend))
        .add("backend_name", game.world().backendName())
        .add("precision", precisionName(o.precision))
        .add("cpu", sandbox::hostCpuName());
    if (gpu.empty())
        json.addNull("gpu");
    else
        json.add("gpu", gpu);
    json.add("gl_renderer", glRenderer)
        .add("headless", o.headless)
        .add("samples", int64_t(frameSamples))
        .add("exact_depth", exactDepth)
        .add("pipelined", o.pipelined)
        .add("paced_hz", int64_t(o.paceHz))  // 0: frames ran back to back
        .add("record_contacts", o.flashes)
        .add("contact_sweeps", int64_t(o.contactSweeps))      // 0: corebox's own cap
        .add("impact_rounds", int64_t(o.impactRounds))        // 0: corebox's own cap
        .add("contact_listings", int64_t(o.contactListings))  // 0: corebox's own cap
        .add("width", int64_t(o.width))
        .add("height", int64_t(o.height))
        .add("frames", int64_t(samples.size()))
        .add("skipped_frames", int64_t(std::min<size_t>(kSkippedFrames, samples.size())))
        .add("frames_measured", int64_t(frameSummary.count))
        .add("n_start", game.ballsAtStart)
        .add("n_end", int64_t(game.world().particleCount()))
        .add("spawned", game.spawned)
        .add("spawn_refused", game.spawnRefused)
        .add("removed", game.removed)
        .add("fired", game.fired)
        .add("fire_refused", game.fireRefused)
        .add("flashes", game.flashes)
        .add("frame_period_s", kFramePeriod)
        .add("substeps", steps.substeps)
        .add("pair_collisions", steps.pairCollisions)
        .add("wall_collisions", steps.wallCollisions)
        .add("round_cap_hits", steps.roundCapHits)
        .add("contact_listings_made", steps.contactListings)
        .add("overlap_left_max", steps.overlapLeft)  // the deepest a step's contact phase left [contact distances]
        .add("simulated_time", game.world().time())
        .add("state_hash", hex(game.world().stateHash()))  // same inputs, backend and threads: same hash
        .add("dropped_time", steps.droppedTime)
        .add("wall_s", wallSeconds)
        .add("sim_ms", summary(&FrameSample::simMs))
        .add("impacts_ms", summary(&FrameSample::impactsMs))
        .add("contacts_ms", summary(&FrameSample::contactsMs))
        .add("listings_ms", summary(&FrameSample::listingsMs))
        .add("render_ms", summary(&FrameSample::renderMs))
        .add("wait_ms", summary(&FrameSample::waitMs))
        .add("frame_ms", frameSummary)
        .add("measured_s", measuredSeconds)  // from the first measured frame's start to the last one's present
        .add("fps_mean", measuredSeconds > 0 ? double(frameSummary.count) / measuredSeconds : 0.0);
    const Sandbox::Soundness end = game.soundness();
    json.add("kinetic_per_ball_end", end.kineticPerBall).add("max_overlap_end", end.maxOverlap);
    // Every frame, the skipped ones too (scripts/plot_sandbox_frames.py draws them against time).
    json.add("per_frame_frame_ms", sandbox::column(samples, 0, &FrameSample::frameMs))
        .add("per_frame_sim_ms", sandbox::column(samples, 0, &FrameSample::simMs))
        .add("per_frame_impacts_ms", sandbox::column(samples, 0, &FrameSample::impactsMs))
        .add("per_frame_contacts_ms", sandbox::column(samples, 0, &FrameSample::contactsMs))
        .add("per_frame_render_ms", sandbox::column(samples, 0, &FrameSample::renderMs))
        .add("per_frame_listings", sandbox::column(samples, 0, &FrameSample::listings))
        .add("per_frame_overlap_left", sandbox::column(samples, 0, &FrameSample::overlapLeft));
    std::ofstream out(o.statsPath);
    out << json.text(true) << "\n";
    out.close();
    if (!out) throw UsageError("--stats: cannot write '" + o.statsPath + "'");
}

int run(const Options& o) {
    const sandbox::Script script = o.scripted             ? sandbox::builtInScript()
                                   : o.scriptPath.empty() ? sandbox::Script{}
                                                          : sandbox::loadScript(o.scriptPath);
    Sandbox game(o);
    const ViewMap map{game.box()};

    std::unique_ptr<Frontend> frontend;
    std::string contextDescription;
    if (o.headless) {
        auto headless = std::make_unique<HeadlessFrontend>(o);
        contextDescription = headless->description();
        frontend = std::move(headless);
    } else {
        if (!corebox::GlfwWindow::displayAvailable())
            throw corebox::PlatformError("no display (DISPLAY and WAYLAND_DISPLAY are unset): run with --headless");
        frontend = std::make_unique<WindowFrontend>(o);
    }
    const std::string glRenderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
    const std::string multisampling =
        frontend->samples() > 1 ? std::to_string(frontend->samples()) + " samples a pixel" : "no multisampling";
    // Flat depth where it pays: a software rasteriser then tests depth before shading (RenderStyle::exactDepth).
    const bool exactDepth = o.depth == SphereDepth::Exact ||
                            (o.depth == SphereDepth::Auto && !corebox::GlfwWindow::isSoftwareRenderer(glRenderer));
    std::fprintf(stderr,
                 "[sandbox] corebox %s, World on %s (%s), %lld balls; drawing with %s%s, %s, %s depth; %s frames\n",
                 corebox::version(), game.world().backendName().c_str(), precisionName(o.precision),
                 (long long)game.ballsAtStart, glRenderer.c_str(), o.headless ? " (headless)" : "",
                 multisampling.c_str(), exactDepth ? "exact" : "flat", o.pipelined ? "pipelined" : "sequential");
    if (!contextDescription.empty())
        std::fprintf(stderr, "[sandbox] headless context: %s\n", contextDescription.c_str());

    corebox::ParticleRenderer renderer;
    std::vector<corebox::ParticleInstance> instances;
    Sandbox::Drawn drawn;  // what the frame draws, copied out of the world (Sandbox::copyDrawn)
    corebox::OrbitCamera camera;
    int width = 0, height = 0;
    frontend->drawableSize(&width, &height);
    const std::array<float, 3> renderBox = map.renderBox();
    camera.frameBox({renderBox[0], renderBox[1], renderBox[2]}, float(width) / float(std::max(height, 1)));

    std::vector<sandbox::FrameSample> samples;
    sandbox::Window second;
    sandbox::Window shown;  // the last second's figures, on the HUD and in the title
    double shownFps = 0;
    StepTotals steps;
    // Pipelined frames: the step of frame k + 1 runs on the worker while frame k is drawn (the drawing is
    // built from its own copy of the state, Sandbox::Drawn). The world is touched by one thread at a time:
    // the main thread waits for the step before it applies the next frame's input, so the world sees
    // the same calls in the same order as when it steps and then draws (the same state hash), and
    // input still acts on the next step. What is drawn is the state before that step.
    struct Posted {
        corebox::StepInfo info;
        double ms = 0;
    } posted;
    std::optional<sandbox::FrameWorker> worker;  // after what its job uses: destroyed first, so a running step ends first
    if (o.pipelined) worker.emplace();
    bool stepping = false;
    auto finishStep = [&](sandbox::FrameSample& sample) {
        Clock::time_point t = Clock::now();
        worker->wait();
        sample.waitMs = msSince(t);
        stepping = false;
        game.noteImpacts();
        steps.add(posted.info);
        sample.simMs = posted.ms;
        return posted.info;
    };

    const Clock::time_point start = Clock::now();
    Clock::time_point lastReport = start;
    // Paced frames (--pace): each starts at a refresh of a fixed grid, its time counted from that refresh,
    // so a frame past the period is one a 60 Hz display would have shown a refresh late. The pipelined
    // step goes on while the loop waits: the period is what one frame's step and drawing share.
    Clock::time_point refresh = start;
    // The measured frames' span (after the first kSkippedFrames), for the session's frame rate.
    Clock::time_point measuredStart = start;
    double measuredSeconds = 0;
    const Clock::duration period =
        std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(o.paceHz > 0 ? 1.0 / o.paceHz : 0.0));
    for (int64_t frame = 0;; ++frame) {
        const Clock::time_point frameStart = o.paceHz > 0 ? refresh : Clock::now();
        if (frame == kSkippedFrames) measuredStart = frameStart;
        bool closed = false;
        std::vector<sandbox::Command> commands = frontend->poll(&closed);
        const auto scripted = script.equal_range(frame);
        for (auto it = scripted.first; it != scripted.second; ++it) commands.push_back(it->second);
        frontend->drawableSize(&width, &height);
        if (width <= 0 || height <= 0) {  // minimised: no frame to draw, no time to advance
            if (closed || g_interrupted) break;
            glfwWaitEventsTimeout(0.1);
            refresh = Clock::now();  // paced: the grid starts again when there is a frame to draw
            --frame;
            continue;
        }
        const float aspect = float(width) / float(height);
        sandbox::FrameSample sample;
        corebox::StepInfo info;
        if (stepping) info = finishStep(sample);

        // Input: the user's and the script's, through the same calls.
        bool quit = closed || g_interrupted;
        std::vector<std::string> screenshots;
        for (const sandbox::Command& c : commands) {
            const bool log = !c.origin.empty();
            switch (c.kind) {
                case sandbox::CommandKind::Spawn: {
                    const Sandbox::Outcome r = game.spawn(cursorRay(camera, map, c.u, c.v, aspect), c.repeat);
                    if (log && r.at)
                        std::fprintf(stderr,
                                     "[sandbox] frame %lld (%s): click %.2f %.2f -> %lld spawned, %lld refused at "
                                     "(%.1f, %.1f, %.1f)\n",
                                     (long long)frame, c.origin.c_str(), c.u, c.v, (long long)r.done,
                                     (long long)r.refused, r.at->x, r.at->y, r.at->z);
                    break;
                }
                case sandbox::CommandKind::Remove: {
                    const Sandbox::Outcome r = game.remove(cursorRay(camera, map, c.u, c.v, aspect));
                    if (log && r.at)
                        std::fprintf(
                            stderr,
                            "[sandbox] frame %lld (%s): remove %.2f %.2f -> %lld removed near (%.1f, %.1f, %.1f)\n",
                            (long long)frame, c.origin.c_str(), c.u, c.v, (long long)r.done, r.at->x, r.at->y, r.at->z);
                    break;
                }
                case sandbox::CommandKind::Fire: {
                    const Sandbox::Outcome r = game.fire(map.toWorld(camera.eye()));
                    if (log && r.at)
                        std::fprintf(stderr, "[sandbox] frame %lld (%s): fire -> heavy ball from (%.1f, %.1f, %.1f)\n",
                                     (long long)frame, c.origin.c_str(), r.at->x, r.at->y, r.at->z);
                    if (log && !r.at)
                        std::fprintf(stderr, "[sandbox] frame %lld (%s): fire -> no free place on the line\n",
                                     (long long)frame, c.origin.c_str());
                    break;
                }
                case sandbox::CommandKind::Orbit:
                    camera.orbit(float(c.u), float(c.v));
                    break;
                case sandbox::CommandKind::Zoom:
                    camera.zoom(float(c.u));
                    break;
                case sandbox::CommandKind::Screenshot:
                    screenshots.push_back(c.path);
                    break;
                case sandbox::CommandKind::Quit:
                    quit = true;
                    break;
            }
        }

        // Simulation, sequential frames: one fixed frame period, then the state the renderer reads (a
        // download on CUDA).
        Clock::time_point t = Clock::now();
        if (!o.pipelined) {
            info = game.advanceFrame();
            game.world().positions();
            sample.simMs = msSince(t);
            game.noteImpacts();
            steps.add(info);
        }

        // Drawing: what the frame reports of the world is copied out of it here, before a pipelined step
        // takes the world; the particle view, the legend and the HUD lines are built from that copy while
        // the step runs.
        t = Clock::now();
        game.copyDrawn(map, drawn);
        // Pipelined: the next frame's step, now that everything drawn is copied out of the world.
        if (worker) {
            worker->post([&] {
                const Clock::time_point t0 = Clock::now();
                posted.info = game.advanceFrame();
                game.world().positions();
                posted.ms = msSince(t0);
            });
            stepping = true;
        }
        game.buildInstances(drawn, instances);
        const std::vector<std::string> hud{
            shown.frames == 0
                ? std::string("measuring...")
                : format("sim %.2f ms   render %.2f ms   frame %.2f ms   %.1f fps", shown.mean(shown.simMs),
                         shown.mean(shown.renderMs), shown.mean(shown.frameMs), shownFps),
            std::string(backendName(o.backend)) + " " + precisionName(o.precision) + "   " +
                format("t %.2f   %.0f substeps of 1/240 this frame", drawn.time, double(info.substeps)),
            format("spawned %.0f (%.0f refused)   removed %.0f   fired %.0f", double(game.spawned),
                   double(game.spawnRefused), double(game.removed), double(game.fired)),
            "left click: spawn   right click: remove   space: fire   arrows: orbit"};
        corebox::RenderStyle style = game.style(drawn, hud);
        style.exactDepth = exactDepth;
        renderer.upload(instances.data(), instances.size());
        frontend->bindTarget();
        renderer.render(camera, renderBox, style, width, height);
        glFinish();  // the frame's GL work is in its render time, not in the next frame's
        sample.renderMs = msSince(t);

        const bool last = quit || (o.frames > 0 && frame + 1 >= o.frames);
        if (last && !o.screenshotPath.empty()) screenshots.push_back(o.screenshotPath);
        double screenshotMs = 0;
        if (!screenshots.empty()) {
            t = Clock::now();
            const corebox::Image image = frontend->readFrame(width, height);
            for (const std::string& path : screenshots) {
                corebox::writePng(path, image);
                std::fprintf(stderr, "[sandbox] frame %lld written to %s\n", (long long)frame, path.c_str());
            }
            screenshotMs = msSince(t);
        }
        frontend->present();
        sample.frameMs = msSince(frameStart) - screenshotMs;
        sample.impactsMs = 1e3 * info.secondsImpacts;
        sample.contactsMs = 1e3 * info.secondsContacts;
        sample.listingsMs = 1e3 * info.secondsListings;
        sample.listings = info.contactListings;
        sample.overlapLeft = info.overlapLeft;
        samples.push_back(sample);
        second.add(sample);

        // Once a second: the HUD's figures, the title, a line on stderr.
        if (msSince(lastReport) >= 1000.0 || last) {
            const double simMs = second.mean(second.simMs), renderMs = second.mean(second.renderMs);
            const double frameMs = second.mean(second.frameMs);
            const double fps = second.fps(msSince(lastReport));
            frontend->setTitle("corebox sandbox - " + std::to_string(drawn.x.size()) + " balls - " +
                               format("sim %.2f ms, render %.2f ms, %.1f fps", simMs, renderMs, fps));
            std::fprintf(stderr,
                         "[sandbox] frame %lld, t %.2f: %d frames, %.1f fps; sim %.2f ms (max %.2f; impacts %.2f, "
                         "contacts %.2f), render %.2f ms, frame %.2f ms; %zu balls\n",
                         (long long)frame, drawn.time, second.frames, fps, simMs, second.simMaxMs,
                         second.mean(second.impactsMs), second.mean(second.contactsMs), renderMs, frameMs,
                         drawn.x.size());
            shown = second;
            shownFps = fps;
            second = sandbox::Window{};
            lastReport = Clock::now();
        }
        if (last) {
            if (frame >= kSkippedFrames) measuredSeconds = 1e-3 * msSince(measuredStart);
            break;
        }
        if (o.paceHz > 0) {
            Clock::time_point next = refresh + period;
            const Clock::time_point now = Clock::now();
            if (now > next) next += period * ((now - next) / period + 1);  // missed: the refresh after now
            std::this_thread::sleep_until(next);
            refresh = next;
        }
    }
    if (stepping) {  // the step posted with the last frame: part of the session, not of a frame's time
        sandbox::FrameSample unused;
        finishStep(unused);
    }
    const double wallSeconds = 1e-3 * msSince(start);

    const sandbox::Summary s = sandbox::summarise(sandbox::column(samples, kSkippedFrames, &sandbox::FrameSample::simMs));
    const sandbox::Summary f = sandbox::summarise(sandbox::column(samples, kSkippedFrames, &sandbox::FrameSample::frameMs));
    std::fprintf(stderr,
                 "[sandbox] %zu frames, %zu balls at the end; after the first %d frames: sim mean %.2f median %.2f p95 "
                 "%.2f max %.2f ms, "
                 "frame mean %.2f median %.2f p95 %.2f max %.2f ms\n",
                 samples.size(), game.world().particleCount(), kSkippedFrames, s.mean, s.median, s.p95, s.max, f.mean,
                 f.median, f.p95, f.max);
    if (!o.statsPath.empty()) {
        writeStats(o, game, samples, steps, wallSeconds, measuredSeconds, glRenderer, frontend->samples(), exactDepth);
        std::fprintf(stderr, "[sandbox] statistics written to %s\n", o.statsPath.c_str());
    }
    return g_interrupted ? 130 : 0;
}

}  // namespace

int main(int argc, char** argv) {
    std::signal(SIGINT, onSignal);
    std::signal(SIGTERM, onSignal);
    Options options;
    try {
        options = parseOptions(argc, argv);
    } catch (const UsageError& e) {
        std::fprintf(stderr, "sandbox: %s (sandbox --help lists the options)\n", e.what());
        return 2;
    }
    try {
        return run(options);
    } catch (const UsageError& e) {
        std::fprintf(stderr, "sandbox: %s\n", e.what());
        return 2;
    } catch (const sandbox::ScriptError& e) {
        std::fprintf(stderr, "sandbox: %s\n", e.what());
        return 2;
    } catch (const corebox::InputError& e) {
        std::fprintf(stderr, "sandbox: %s\n", e.what());
        return 2;
    } catch (const corebox::InstabilityError& e) {
        std::fprintf(stderr, "sandbox: the simulation blew up: %s\n", e.what());
        return 3;
    } catch (const corebox::DeviceError& e) {
        std::fprintf(stderr, "sandbox: device error: %s\n", e.what());
        return 4;
    } catch (const corebox::PlatformError& e) {
        const bool hinted = options.headless || std::string(e.what()).find("--headless") != std::string::npos;
        std::fprintf(stderr, "sandbox: %s%s\n", e.what(), hinted ? "" : " (no display? try --headless)");
        return 4;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "sandbox: %s\n", e.what());
        return 1;
    }
}
