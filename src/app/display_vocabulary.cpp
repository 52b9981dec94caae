#include "display_vocabulary.h"

#include <cstdio>

namespace corebox {
namespace {

constexpr Term<ColorMode> kColorModes[] = {{ColorMode::Species, "species", ""}, {ColorMode::Speed, "speed", ""}};
constexpr Vocabulary<ColorMode> kColorModeTable("colour mode", kColorModes);

}  // namespace

const Vocabulary<ColorMode>& colorModeTable() { return kColorModeTable; }

bool parseFrameSize(const std::string& text, FrameSize* size) {
    int w = 0, h = 0;
    char x = 0, extra = 0;
    if (std::sscanf(text.c_str(), "%d%c%d%c", &w, &x, &h, &extra) != 3 || (x != 'x' && x != 'X')) return false;
    if (w < kMinFrameSide || h < kMinFrameSide || w > kMaxFrameSide || h > kMaxFrameSide) return false;
    *size = {w, h};
    return true;
}

std::string frameSizeName(FrameSize size) { return std::to_string(size.width) + "x" + std::to_string(size.height); }

std::string frameSizeProblem(const std::string& text) {
    return "expected WIDTHxHEIGHT with each between " + std::to_string(kMinFrameSide) + " and " + std::to_string(kMaxFrameSide) +
           ", got '" + text + "'";
}

}  // namespace corebox
