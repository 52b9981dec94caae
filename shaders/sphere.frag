#version 450 core
// Ray-sphere intersection per fragment: exact silhouette, per-pixel normal, Blinn-Phong lighting
// and the true depth of the hit point, so spheres intersect and occlude correctly (unless
// COREBOX_FLAT_DEPTH, below).
in vec3 vRayPoint;
flat in vec3 vCentre;
flat in float vRadius;
flat in float vColorKey;

uniform mat4 uProjection;
uniform int uColorMode;          // 0: species palette, 1: speed colormap
uniform vec3 uPalette[32];
uniform int uPaletteSize;
uniform vec2 uKeyRange;          // speed mode: key mapped from [x, y] to [0, 1]

out vec4 fragColor;
// The hit point is never nearer than the quad (sphere.vert puts it before the tangent plane nearest the eye):
// with the depth only ever raised, the depth test rejects fragments behind what is drawn before shading
// them, as it would for a shader that writes no depth. The sandbox example at 10^5 balls on an H200
// (fp32, 4 samples, separate binaries alternating in one call, three runs each): 3.2 to 3.5 ms a frame of
// drawing against 4.3 to 4.5 in the landing, and the step that draws alongside slowed less (frames 7.6 to
// 7.9 ms on average against 8.2 to 8.3); the landing's frame at 180 differed from the old drawing in 0.2%
// of its pixels (ties where touching spheres meet). Mesa's llvmpipe draws no faster for it.
// COREBOX_FLAT_DEPTH (RenderStyle::exactDepth false): no depth written; each sphere keeps its quad's depth,
// that of its point nearest the eye, so the depth test runs before shading (a software rasteriser's
// early test) and hidden fragments are never shaded.
#ifndef COREBOX_FLAT_DEPTH
layout(depth_greater) out float gl_FragDepth;
#endif

vec3 viridis(float t);

void main() {
    vec3 dir = normalize(vRayPoint);
    float b = dot(dir, vCentre);
    float c = dot(vCentre, vCentre) - vRadius * vRadius;
    float disc = b * b - c;
    if (disc < 0.0) discard;
    float t = b - sqrt(disc);
    vec3 hit = t * dir;
    vec3 normal = (hit - vCentre) / vRadius;

    vec3 base;
    if (uColorMode == 0) {
        int index = clamp(int(vColorKey + 0.5), 0, max(uPaletteSize - 1, 0));
        base = uPalette[index];
    } else {
        float span = max(uKeyRange.y - uKeyRange.x, 1e-12);
        base = viridis(clamp((vColorKey - uKeyRange.x) / span, 0.0, 1.0));
    }

    // A key light above-left of the camera and a weak fill from the camera.
    vec3 light = normalize(vec3(-0.35, 0.55, 0.75));
    vec3 view = -dir;
    float diffuse = max(dot(normal, light), 0.0);
    float fill = max(dot(normal, view), 0.0);
    float specular = pow(max(dot(normal, normalize(light + view)), 0.0), 48.0);
    vec3 color = base * (0.18 + 0.62 * diffuse + 0.25 * fill) + vec3(0.28) * specular;
    fragColor = vec4(color, 1.0);

#ifndef COREBOX_FLAT_DEPTH
    vec4 clip = uProjection * vec4(hit, 1.0);
    gl_FragDepth = 0.5 * (clip.z / clip.w) + 0.5;
#endif
}
