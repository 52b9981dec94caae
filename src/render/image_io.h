// PNG files for frames, screenshots and golden images (stb_image_write / stb_image). Writes go to a
// temporary name beside the target and are renamed into place, so a frame is whole or absent.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace corebox {

struct Image {
    int width = 0, height = 0;
    std::vector<uint8_t> rgba;  // rows top to bottom
};

// Throws std::runtime_error naming the path on failure.
void writePng(const std::string& path, const Image& image);
// Bytes (an encoded PNG) to `path` through a temporary and a rename.
void writeFileAtomic(const std::string& path, const std::vector<uint8_t>& bytes);
// PNG encoded in memory (for the video pipe's timing and for tests).
std::vector<uint8_t> encodePng(const Image& image);
Image readPng(const std::string& path);
// GL reads rows bottom-up; images are top-down.
void flipRows(std::vector<uint8_t>& rgba, int width, int height);

}  // namespace corebox
