#include "image_io.h"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <stb/stb_image.h>
#include <stb/stb_image_write.h>

namespace corebox {
namespace {

void appendBytes(void* context, void* data, int size) {
    auto* out = static_cast<std::vector<uint8_t>*>(context);
    const uint8_t* bytes = static_cast<const uint8_t*>(data);
    out->insert(out->end(), bytes, bytes + size);
}

}  // namespace

std::vector<uint8_t> encodePng(const Image& image) {
    // Level 2 of zlib's 0..9: frames are mostly flat background, so it compresses nearly as well as
    // the default 8 at a fraction of the time (PNG encoding dominates headless frame time). Set
    // once, thread-safely: frames are encoded on several threads.
    static const bool configured = (stbi_write_png_compression_level = 2, true);
    (void)configured;
    std::vector<uint8_t> png;
    if (!stbi_write_png_to_func(appendBytes, &png, image.width, image.height, 4, image.rgba.data(), image.width * 4)) {
        throw std::runtime_error("PNG encoding failed");
    }
    return png;
}

void writePng(const std::string& path, const Image& image) { writeFileAtomic(path, encodePng(image)); }

void writeFileAtomic(const std::string& path, const std::vector<uint8_t>& png) {
    const std::string temp = path + ".tmp-" + std::to_string(::getpid());
    std::FILE* f = std::fopen(temp.c_str(), "wb");
    if (!f) throw std::runtime_error("cannot write '" + path + "': " + std::strerror(errno));
    const bool written = std::fwrite(png.data(), 1, png.size(), f) == png.size();
    const bool closed = std::fclose(f) == 0;
    if (!written || !closed || std::rename(temp.c_str(), path.c_str()) != 0) {
        const std::string reason = std::strerror(errno);
        std::remove(temp.c_str());
        throw std::runtime_error("cannot write '" + path + "': " + reason);
    }
}

void flipRows(std::vector<uint8_t>& rgba, int width, int height) {
    const size_t row = size_t(width) * 4;
    for (int y = 0; y < height / 2; ++y) {
        std::swap_ranges(rgba.begin() + long(size_t(y) * row), rgba.begin() + long(size_t(y + 1) * row),
                         rgba.begin() + long(size_t(height - 1 - y) * row));
    }
}

Image readPng(const std::string& path) {
    Image image;
    int channels = 0;
    unsigned char* data = stbi_load(path.c_str(), &image.width, &image.height, &channels, 4);
    if (!data) throw std::runtime_error("cannot read PNG '" + path + "': " + stbi_failure_reason());
    image.rgba.assign(data, data + size_t(image.width) * size_t(image.height) * 4);
    stbi_image_free(data);
    return image;
}

}  // namespace corebox
