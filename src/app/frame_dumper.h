// Headless frames: an EGL context, the renderer and an offscreen target; each frame becomes
// DIR/frame_NNNNNN.png (written whole, then renamed) and, optionally, a video through ffmpeg.
// PNG encoding, the slowest part of a frame on the CPU, runs on background threads (one per
// hardware thread, a bounded number of frames in flight) while the next frames are simulated and
// drawn. Timing of render, read-back and the wait for the encoders is kept for the report.
//
// Every file written here was named by the user (--out, --video, --screenshot, a script), so a
// failure to write one is an input/output problem: InputError naming the path (exit code 2).
#pragma once

#include <cstdint>
#include <chrono>
#include <cstdio>
#include <deque>
#include <future>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "atomic_file.h"
#include "egl_headless_context.h"
#include "image_io.h"
#include "offscreen_target.h"
#include "orbit_camera.h"
#include "particle_renderer.h"

namespace corebox {

struct FrameDumpOptions {
    std::string outDir;
    int width = 1280, height = 720;
    std::string videoPath;  // "" : no video
    int videoFps = 30;
    bool writePng = true;  // false: frames are rendered and read back (video, screenshots) but not encoded
    HeadlessContextOptions context;
};

struct FrameTimings {
    double render = 0, readback = 0;  // seconds, summed over frames
    double encodeWait = 0;            // seconds spent waiting for the PNG encoders to catch up
    double wall = 0;                  // from the first frame to the last file written
    int64_t frames = 0;
    int encoders = 1;
};

class FrameDumper {
public:
    // Throws PlatformError (no EGL), RenderError, or InputError for ffmpeg problems.
    FrameDumper(const FrameDumpOptions& options, const std::array<float, 3>& boxSize);
    ~FrameDumper();

    const std::string& contextDescription() const { return m_context.description(); }
    ParticleRenderer& renderer() { return *m_renderer; }
    OrbitCamera& camera() { return m_camera; }

    // Renders what the renderer's buffer holds, then `overlay` (the HUD) when given, and writes
    // frame number `index`.
    void writeFrame(int64_t index, const RenderStyle& style, const std::function<void(int, int)>& overlay = {});
    const Image& lastImage() const { return m_image; }
    // Waits for every PNG to be written (rethrowing a write error as InputError) and closes the video (renaming
    // it into place). Returns false when ffmpeg reported an error.
    bool finish();
    const FrameTimings& timings() const { return m_timings; }

    static std::string framePath(const std::string& dir, int64_t index);

private:
    FrameDumpOptions m_options;
    std::array<float, 3> m_box;
    EglHeadlessContext m_context;
    std::unique_ptr<ParticleRenderer> m_renderer;
    std::unique_ptr<OffscreenTarget> m_target;
    OrbitCamera m_camera;
    Image m_image;
    std::FILE* m_video = nullptr;
    OutputTarget m_videoTarget;
    std::string m_videoTemp;  // "" when ffmpeg writes to a device or FIFO directly
    int m_videoSlot = -1;     // the temporary's entry in atomic_file.h's registry
    FrameTimings m_timings;
    std::deque<std::future<void>> m_encoding;
    std::chrono::steady_clock::time_point m_firstFrame;
};

// Throws InputError with advice when ffmpeg is not on PATH.
void requireFfmpeg();

// Throws InputError unless the video path ends in a container ffmpeg writes H.264 into (.mp4, .mkv,
// .mov, .avi): checked when the run starts, not when ffmpeg refuses the file after the first frame.
void checkVideoPath(const std::string& path);

// writePng for a file the user asked for (frames, screenshots): throws InputError naming the path.
void writeOutputPng(const std::string& path, const Image& image);

}  // namespace corebox
