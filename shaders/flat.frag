#version 450 core
// One colour per draw (box edges).
uniform vec4 uColor;
out vec4 fragColor;
void main() { fragColor = uColor; }
