#include "frame_dumper.h"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <memory>
#include <thread>
#include <cstdlib>
#include <stdexcept>

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

void writeOutputPng(const std::string& path, const Image& image) {
    asOutput(path, [&] { writePng(path, image); });
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
        // ffmpeg picks the container from the extension, so the temporary keeps it.
        const size_t dot = options.videoPath.find_last_of('.');
        const std::string ext = dot == std::string::npos ? ".mp4" : options.videoPath.substr(dot);
        m_videoTemp = options.videoPath + ".tmp-" + std::to_string(::getpid()) + ext;
        const std::string cmd = "ffmpeg -loglevel error -y -f rawvideo -pix_fmt rgba -s " + std::to_string(options.width) + "x" +
                                std::to_string(options.height) + " -r " + std::to_string(options.videoFps) +
                                " -i - -c:v libx264 -pix_fmt yuv420p -vf " + shellQuote("pad=ceil(iw/2)*2:ceil(ih/2)*2") + " " +
                                shellQuote(m_videoTemp);
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
        std::remove(m_videoTemp.c_str());
    }
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
    if (m_video && std::fwrite(m_image.rgba.data(), 1, m_image.rgba.size(), m_video) != m_image.rgba.size()) {
        throw InputError("--video: ffmpeg stopped accepting frames for " + m_options.videoPath);
    }
    // Encode and write in the background; wait only when every encoder is busy.
    t = Clock::now();
    while (m_encoding.size() >= size_t(m_timings.encoders)) {
        m_encoding.front().get();
        m_encoding.pop_front();
    }
    m_timings.encodeWait += since(t);
    auto image = std::make_shared<const Image>(m_image);
    const std::string path = framePath(m_options.outDir, index);
    m_encoding.push_back(std::async(std::launch::async, [image, path] { asOutput(path, [&] { writeFileAtomic(path, encodePng(*image)); }); }));
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
    if (status != 0 || std::rename(m_videoTemp.c_str(), m_options.videoPath.c_str()) != 0) {
        std::remove(m_videoTemp.c_str());
        return false;
    }
    return true;
}

}  // namespace corebox
