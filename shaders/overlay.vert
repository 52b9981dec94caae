#version 450 core
// Screen-space overlay (legend bar, swatches, text): pixel coordinates with y down, per-vertex
// colour, and a colormap coordinate for the speed bar (negative: use the vertex colour).
layout(location = 0) in vec2 inPixel;
layout(location = 1) in vec4 inColor;
layout(location = 2) in float inColormapT;
uniform vec2 uViewportSize;
out vec4 vColor;
out float vColormapT;
void main() {
    vec2 ndc = vec2(inPixel.x / uViewportSize.x * 2.0 - 1.0, 1.0 - inPixel.y / uViewportSize.y * 2.0);
    gl_Position = vec4(ndc, 0.0, 1.0);
    vColor = inColor;
    vColormapT = inColormapT;
}
