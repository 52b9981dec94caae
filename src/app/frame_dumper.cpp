#include "frame_dumper.h"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <memory>
#include <thread>
#include <cstdlib>
#include <stdexcept>

#include "atomic_file.h"
#include "errors.h"

namespace corebox {
namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

std::string shellQuote(const std::string& s) {
    std::string out = "'";
    for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return out + "'";
}

// image_io reports with std::runtime_error; its messages name the path, except an encoding failure.
template <class Write>
void asOutput(const std::string& path, Write&& write) {
    try {
        write();
    } catch (const std::runtime_error& e) {
        const std::string what = e.what();
        throw InputError(what.find(path) == std::string::npos ? "cannot write '" + path + "': " + what : what);
    }
}

}  // namespace

void requireFfmpeg() {
    if (std::system("command -v ffmpeg >/dev/null 2>&1") != 0) {
        throw InputError("--video needs ffmpeg, which is not installed (apt-get install ffmpeg), or leave out --video");
    }
}

namespace {

// Through atomic_file.h, so a frame or screenshot path that is a link, a device or a FIFO is treated
// like every other output, and an interrupted run leaves no half-written PNG under a temporary name.
void writePngBytes(const std::string& path, const std::vector<uint8_t>& png) {
    writeOutputFile(path, std::string(png.begin(), png.end()));
}

}  // namespace

void writeOutputPng(const std::string& path, const Image& image) {
    asOutput(path, [&] { writePngBytes(path, encodePng(image)); });
}

void checkVideoPath(const std::string& path) {
    const size_t slash = path.find_last_of('/');
    const size_t dot = path.find_last_of('.');
    const std::string ext = dot == std::string::npos || (slash != std::string::npos && dot < slash) ? "" : path.substr(dot + 1);
    for (const char* known : {"mp4", "mkv", "mov", "avi"}) {
        if (ext == known) return;
    }
    throw InputError("--video: '" + path + "' has " + (ext.empty() ? std::string("no extension") : "the extension ." + ext) +
                     "; the container comes from it: one of .mp4, .mkv, .mov, .avi (H.264 video)");
}

FrameDumper::FrameDumper(const FrameDumpOptions& options, const std::array<float, 3>& boxSize)
    : m_options(options), m_box(boxSize), m_context(options.context) {
    m_renderer = std::make_unique<ParticleRenderer>();
    m_target = std::make_unique<OffscreenTarget>(options.width, options.height);
    m_camera.frameBox({boxSize[0], boxSize[1], boxSize[2]}, float(options.width) / float(options.height));
    m_image.width = options.width;
    m_image.height = options.height;
    m_timings.encoders = std::max(1, int(std::thread::hardware_concurrency()));
    if (!options.videoPath.empty()) {
        requireFfmpeg();
        checkVideoPath(options.videoPath);
        // ffmpeg picks the container from the extension, so the temporary keeps it; it lies beside
        // the file a link names, so that the rename replaces that file and keeps the link.
        m_videoTarget = inspectOutput(options.videoPath);
        const size_t dot = options.videoPath.find_last_of('.');
        const std::string ext = options.videoPath.substr(dot);
        if (m_videoTarget.kind == OutputKind::Regular || m_videoTarget.kind == OutputKind::Missing) {
            m_videoTemp = m_videoTarget.target + ".tmp-" + std::to_string(::getpid()) + ext;
            m_videoSlot = registerTemporaryFile(m_videoTemp);
        }
        // setsid: ffmpeg in a session of its own, so the terminal's Ctrl-C reaches corebox alone,
        // which then closes the video properly (interruption.h) instead of losing it with ffmpeg.
        const std::string output = m_videoTemp.empty() ? m_videoTarget.target : m_videoTemp;
        const std::string format = m_videoTemp.empty() ? " -f " + std::string(ext == ".mkv" ? "matroska" : ext.substr(1)) : "";
        const std::string cmd = "exec setsid ffmpeg -loglevel error -y -f rawvideo -pix_fmt rgba -s " + std::to_string(options.width) + "x" +
                                std::to_string(options.height) + " -r " + std::to_string(options.videoFps) +
                                " -i - -c:v libx264 -pix_fmt yuv420p -vf " + shellQuote("pad=ceil(iw/2)*2:ceil(ih/2)*2") + format + " " +
                                shellQuote(output);
        m_video = ::popen(cmd.c_str(), "w");
        if (!m_video) throw InputError("--video: cannot start ffmpeg for " + options.videoPath);
    }
}

FrameDumper::~FrameDumper() {
    for (std::future<void>& f : m_encoding) {
        try {
            f.get();
        } catch (const std::exception&) {  // already failing: the first error was reported
        }
    }
    if (m_video) {
        ::pclose(m_video);
        if (!m_videoTemp.empty()) std::remove(m_videoTemp.c_str());
    }
    releaseTemporaryFile(m_videoSlot);
}

std::string FrameDumper::framePath(const std::string& dir, int64_t index) {
    char name[32];
    std::snprintf(name, sizeof name, "frame_%06lld.png", (long long)index);
    return dir + "/" + name;
}

void FrameDumper::writeFrame(int64_t index, const RenderStyle& style, const std::function<void(int, int)>& overlay) {
    Clock::time_point t = Clock::now();
    m_target->bind();
    m_renderer->render(m_camera, m_box, style, m_options.width, m_options.height);
    if (overlay) overlay(m_options.width, m_options.height);
    glFinish();
    m_timings.render += since(t);
    t = Clock::now();
    m_target->readPixels(m_image.rgba);
    m_timings.readback += since(t);
    if (m_timings.frames == 0) m_firstFrame = Clock::now();
    if (!m_options.writePng) ++m_timings.frames;
    if (m_video && std::fwrite(m_image.rgba.data(), 1, m_image.rgba.size(), m_video) != m_image.rgba.size()) {
        throw InputError("--video: ffmpeg stopped accepting frames for " + m_options.videoPath);
    }
    if (!m_options.writePng) return;
    // Encode and write in the background; wait only when every encoder is busy.
    t = Clock::now();
    while (m_encoding.size() >= size_t(m_timings.encoders)) {
        m_encoding.front().get();
        m_encoding.pop_front();
    }
    m_timings.encodeWait += since(t);
    auto image = std::make_shared<const Image>(m_image);
    const std::string path = framePath(m_options.outDir, index);
    m_encoding.push_back(std::async(std::launch::async, [image, path] { asOutput(path, [&] { writePngBytes(path, encodePng(*image)); }); }));
    ++m_timings.frames;
}

bool FrameDumper::finish() {
    const Clock::time_point t = Clock::now();
    while (!m_encoding.empty()) {
        m_encoding.front().get();
        m_encoding.pop_front();
    }
    m_timings.encodeWait += since(t);
    if (m_timings.frames > 0) m_timings.wall = since(m_firstFrame);
    if (!m_video) return true;
    const int status = ::pclose(m_video);
    m_video = nullptr;
    bool ok = status == 0;
    if (!m_videoTemp.empty()) {
        ok = ok && std::rename(m_videoTemp.c_str(), m_videoTarget.target.c_str()) == 0;
        if (!ok) std::remove(m_videoTemp.c_str());
    }
    releaseTemporaryFile(m_videoSlot);
    m_videoSlot = -1;
    return ok;
}

}  // namespace corebox
