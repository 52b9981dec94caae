#version 450 core
// Sphere impostor: one camera-facing quad per particle instance (4 vertices, triangle strip from
// gl_VertexID), large enough to cover the sphere's perspective silhouette; the fragment shader
// ray-traces the sphere inside it.
layout(location = 0) in vec4 inPositionRadius;  // per instance: centre (world) and hard-core radius
layout(location = 1) in float inColorKey;       // per instance: species index or speed

uniform mat4 uView;
uniform mat4 uProjection;

out vec3 vRayPoint;       // point on the quad, view space (the ray from the eye passes through it)
flat out vec3 vCentre;    // sphere centre, view space
flat out float vRadius;
flat out float vColorKey;

void main() {
    vec2 corner = vec2((gl_VertexID & 1) != 0 ? 1.0 : -1.0, (gl_VertexID & 2) != 0 ? 1.0 : -1.0);
    vec3 centre = (uView * vec4(inPositionRadius.xyz, 1.0)).xyz;
    float radius = inPositionRadius.w;
    float dist2 = dot(centre, centre);
    // Half-width of the tangent cone at the centre's distance, with margin for off-axis stretch.
    float halfWidth = 1.3 * radius * sqrt(dist2 / max(dist2 - radius * radius, 1e-8));
    vec3 quadPoint = centre + vec3(corner * halfWidth, 0.0);
    vRayPoint = quadPoint;
    vCentre = centre;
    vRadius = radius;
    vColorKey = inColorKey;
    gl_Position = uProjection * vec4(quadPoint, 1.0);
}
