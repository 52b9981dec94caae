#version 450 core
// Sphere impostor: one eye-facing quad per particle instance (4 vertices, triangle strip from
// gl_VertexID), just large enough to cover the sphere's perspective silhouette; the fragment shader
// ray-traces the sphere inside it. The quad lies just before the sphere's tangent plane nearest the eye:
// every point of the sphere is behind it, so the depth the fragment shader writes is never less than
// the quad's (sphere.frag: depth_greater), and the depth test can reject hidden fragments before
// shading. The renderer clamps depth for this pass (particle_renderer.cpp): a quad nearer than the near
// plane, of a sphere that reaches beyond it, is not clipped away.
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
    // The quad faces the eye (normal along the ray to the centre) just before the sphere's nearest point,
    // a distance p = d - (1 + kMargin) r from the eye, so the cone of rays tangent to the sphere cuts its
    // plane in a circle of radius r p / sqrt(d^2 - r^2): the quad is that circle's square and no wider (a
    // quad facing the view plane needs a margin for off-axis stretch, and every fragment of the margin is
    // shaded only to be discarded). kMargin keeps every hit depth strictly behind the quad's, where
    // rounding (or a sample off the pixel's centre) at the tangent point would otherwise break
    // depth_greater's promise.
    const float kMargin = 1e-3;
    float dist = sqrt(max(dist2, 1e-12));
    vec3 toCentre = centre / dist;
    vec3 helper = abs(toCentre.y) < 0.99 ? vec3(0.0, 1.0, 0.0) : vec3(1.0, 0.0, 0.0);
    vec3 side = normalize(cross(toCentre, helper));
    vec3 up = cross(side, toCentre);
    float planeDistance = dist - (1.0 + kMargin) * radius;
    float halfWidth = radius * planeDistance * inversesqrt(max(dist2 - radius * radius, 1e-8));
    vec3 quadPoint = planeDistance * toCentre + halfWidth * (corner.x * side + corner.y * up);
    vRayPoint = quadPoint;
    vCentre = centre;
    vRadius = radius;
    vColorKey = inColorKey;
    gl_Position = uProjection * vec4(quadPoint, 1.0);
}
