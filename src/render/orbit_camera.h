// Orbit camera around a target (GLM): yaw and pitch on a sphere of radius `distance`, perspective
// projection. frameBox() puts the whole box in view from a three-quarter angle, the default.
#pragma once

#include <glm/glm.hpp>

namespace corebox {

class OrbitCamera {
public:
    // Centre on the box [0, size] and back off until its bounding sphere fits the vertical and
    // horizontal field of view at the given aspect ratio (width / height).
    void frameBox(const glm::vec3& size, float aspect);

    void orbit(float deltaYaw, float deltaPitch);  // radians
    void zoom(float factor);                       // distance *= factor
    void pan(float dx, float dy);                  // in units of the distance, along screen axes

    glm::mat4 view() const;
    glm::mat4 projection(float aspect) const;
    glm::vec3 eye() const;

    glm::vec3 target{0.0f};
    float distance = 10.0f;
    float yaw = 0.6f;     // around the world z axis (up)
    float pitch = 0.45f;  // above the horizon
    float fovY = 0.7854f;  // 45 degrees
    float nearPlane = 0.05f;
    float farPlane = 1000.0f;
};

// Pixel coordinates (x right, y down, origin top-left) of a world point, for tests and overlays.
glm::vec2 projectToPixel(const OrbitCamera& camera, const glm::vec3& world, int width, int height);

}  // namespace corebox
