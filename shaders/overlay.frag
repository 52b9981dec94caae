#version 450 core
in vec4 vColor;
in float vColormapT;
out vec4 fragColor;
vec3 viridis(float t);
void main() { fragColor = vColormapT >= 0.0 ? vec4(viridis(vColormapT), 1.0) : vColor; }
