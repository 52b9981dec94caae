#version 450 core
// Viridis (perceptually uniform, colour-blind safe): nine samples of matplotlib's table at
// t = 0, 1/8, ..., 1, interpolated linearly.
const vec3 kViridis[9] = vec3[9](
    vec3(0.2670, 0.0049, 0.3294), vec3(0.2788, 0.1755, 0.4834), vec3(0.2297, 0.3224, 0.5457),
    vec3(0.1727, 0.4488, 0.5579), vec3(0.1276, 0.5669, 0.5506), vec3(0.1579, 0.6838, 0.5017),
    vec3(0.3692, 0.7889, 0.3829), vec3(0.6785, 0.8637, 0.1895), vec3(0.9932, 0.9062, 0.1439));

vec3 viridis(float t) {
    float x = clamp(t, 0.0, 1.0) * 8.0;
    int i = min(int(x), 7);
    return mix(kViridis[i], kViridis[i + 1], x - float(i));
}
