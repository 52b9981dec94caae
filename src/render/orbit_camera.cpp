#include "orbit_camera.h"

#include <algorithm>
#include <cmath>
#include <glm/gtc/matrix_transform.hpp>

namespace corebox {

void OrbitCamera::frameBox(const glm::vec3& size, float aspect) {
    target = 0.5f * size;
    const float radius = 0.5f * glm::length(size);
    const float halfFov = 0.5f * std::min(fovY, 2.0f * std::atan(std::tan(0.5f * fovY) * aspect));
    distance = 1.05f * radius / std::sin(halfFov);
    nearPlane = std::max(1e-3f, 0.01f * distance);
    farPlane = distance + 4.0f * radius;
}

void OrbitCamera::orbit(float deltaYaw, float deltaPitch) {
    yaw += deltaYaw;
    pitch = std::clamp(pitch + deltaPitch, -1.55f, 1.55f);
}

void OrbitCamera::zoom(float factor) { distance = std::clamp(distance * factor, 1e-3f, 1e6f); }

void OrbitCamera::pan(float dx, float dy) {
    const glm::mat4 v = view();
    const glm::vec3 right(v[0][0], v[1][0], v[2][0]);
    const glm::vec3 up(v[0][1], v[1][1], v[2][1]);
    target += distance * (-dx * right + dy * up);
}

glm::vec3 OrbitCamera::eye() const {
    const glm::vec3 offset(std::cos(pitch) * std::cos(yaw), std::cos(pitch) * std::sin(yaw), std::sin(pitch));
    return target + distance * offset;
}

glm::mat4 OrbitCamera::view() const { return glm::lookAt(eye(), target, glm::vec3(0, 0, 1)); }

glm::mat4 OrbitCamera::projection(float aspect) const { return glm::perspective(fovY, aspect, nearPlane, farPlane); }

glm::vec2 projectToPixel(const OrbitCamera& camera, const glm::vec3& world, int width, int height) {
    const glm::vec4 clip = camera.projection(float(width) / float(height)) * camera.view() * glm::vec4(world, 1.0f);
    const glm::vec2 ndc = glm::vec2(clip) / clip.w;
    return {0.5f * (ndc.x + 1.0f) * float(width), 0.5f * (1.0f - ndc.y) * float(height)};
}

}  // namespace corebox
