// GLSL sources embedded at build time from shaders/ (cmake/EmbedShaders.cmake). viridis_frag is a
// second fragment-shader unit linked into the programs that colour by speed.
#pragma once

namespace corebox::shaders {

extern const char* const sphere_vert;
extern const char* const sphere_frag;
extern const char* const viridis_frag;
extern const char* const lines_vert;
extern const char* const flat_frag;
extern const char* const overlay_vert;
extern const char* const overlay_frag;

}  // namespace corebox::shaders
