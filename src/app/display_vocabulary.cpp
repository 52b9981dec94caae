#include "display_vocabulary.h"

#include <string>

namespace corebox {
namespace {

constexpr Term<ColorMode> kColorModes[] = {{ColorMode::Species, "species", ""}, {ColorMode::Speed, "speed", ""}};
constexpr Vocabulary<ColorMode> kColorModeTable("colour mode", kColorModes);

}  // namespace

const Vocabulary<ColorMode>& colorModeTable() { return kColorModeTable; }

bool parseFrameSize(const std::string& text, FrameSize* size) {
    // Digits only on each side, read without overflow (sscanf's %d wrapped 4294967312 to 16).
    const size_t x = text.find_first_of("xX");
    if (x == std::string::npos) return false;
    const auto side = [](const std::string& digits, long* value) {
        if (digits.empty() || digits.size() > 6 || digits.find_first_not_of("0123456789") != std::string::npos) return false;
        *value = std::stol(digits);
        return true;
    };
    long w = 0, h = 0;
    if (!side(text.substr(0, x), &w) || !side(text.substr(x + 1), &h)) return false;
    if (w < kMinFrameSide || h < kMinFrameSide || w > kMaxFrameSide || h > kMaxFrameSide) return false;
    *size = {int(w), int(h)};
    return true;
}

std::string frameSizeName(FrameSize size) { return std::to_string(size.width) + "x" + std::to_string(size.height); }

std::string frameSizeProblem(const std::string& text) {
    return "expected WIDTHxHEIGHT with each between " + std::to_string(kMinFrameSide) + " and " + std::to_string(kMaxFrameSide) +
           ", got '" + text + "'";
}

}  // namespace corebox
