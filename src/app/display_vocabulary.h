// The display choices a user spells out: the colour mode (species | speed) and a frame size
// (WIDTHxHEIGHT). They belong to the app rather than the core because ColorMode is the renderer's
// (src/render/particle_view.h); the colour modes use the core's Vocabulary (vocabulary.h) so that
// --color-by, scripts and messages read and list them like every other choice.
#pragma once

#include <string>

#include "render_style.h"  // ColorMode
#include "vocabulary.h"

namespace corebox {

const Vocabulary<ColorMode>& colorModeTable();

struct FrameSize {
    int width = 0, height = 0;  // pixels
};

// "1280x720" (or "1280X720"), each side in [kMinFrameSide, kMaxFrameSide].
constexpr int kMinFrameSide = 16, kMaxFrameSide = 16384;
bool parseFrameSize(const std::string& text, FrameSize* size);
std::string frameSizeName(FrameSize size);
// Why parseFrameSize refused `text`: "expected WIDTHxHEIGHT with each between 16 and 16384, got 'big'".
std::string frameSizeProblem(const std::string& text);

}  // namespace corebox
