#include "viewer/camera_rig.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>

namespace aamap {
namespace {

// Rodrigues' rotation of v by angle about the unit axis.
glm::vec3 rotate(const glm::vec3& v, float angle, const glm::vec3& axis) {
    const float c = std::cos(angle), s = std::sin(angle);
    return v * c + glm::cross(axis, v) * s + axis * glm::dot(axis, v) * (1.0f - c);
}

}  // namespace

CameraRig::CameraRig(const View& start, float pivotDistance)
    : start_(start),
      startDistance_(pivotDistance),
      position_(start.position),
      forward_(glm::normalize(start.direction)),
      worldUp_(glm::normalize(start.up)),
      distance_(pivotDistance) {}

void CameraRig::setDirection(const glm::vec3& forward) {
    // Stop short of the poles: the view's up must stay off the view direction.
    const glm::vec3 f = glm::normalize(forward);
    if (std::abs(glm::dot(f, worldUp_)) < 0.995f) forward_ = f;
}

void CameraRig::orbit(float yaw, float pitch) {
    const glm::vec3 pivot = position_ + forward_ * distance_;
    glm::vec3 offset = position_ - pivot;
    offset = rotate(offset, yaw, worldUp_);
    const glm::vec3 right = glm::normalize(glm::cross(-offset, worldUp_));
    const glm::vec3 pitched = rotate(offset, pitch, right);
    if (std::abs(glm::dot(glm::normalize(pitched), worldUp_)) < 0.995f) offset = pitched;
    position_ = pivot + offset;
    forward_ = glm::normalize(-offset);
}

void CameraRig::look(float yaw, float pitch) {
    glm::vec3 f = rotate(forward_, yaw, worldUp_);
    const glm::vec3 right = glm::normalize(glm::cross(f, worldUp_));
    setDirection(rotate(f, pitch, right));
}

void CameraRig::dolly(float fraction) {
    const float step = std::clamp(fraction, -1.0f, 0.9f) * distance_;
    position_ += forward_ * step;
    distance_ -= step;
}

void CameraRig::fly(const glm::vec3& local) {
    const glm::vec3 right = glm::normalize(glm::cross(forward_, worldUp_));
    const glm::vec3 up = glm::cross(right, forward_);
    position_ += (local.x * right + local.y * up + local.z * forward_) * distance_;
}

View CameraRig::view() const {
    View v = start_;
    v.position = position_;
    v.direction = forward_;
    return v;
}

bool CameraRig::atStart() const {
    return position_ == start_.position && forward_ == glm::normalize(start_.direction);
}

float pivotDistanceFor(const Scene& scene, const View& view) {
    if (scene.mesh.positions.empty()) return 1.0f;
    glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
    for (const glm::vec3& p : scene.mesh.positions) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    const float along = glm::dot((lo + hi) * 0.5f - view.position, glm::normalize(view.direction));
    return std::max(along, 1e-3f * glm::length(hi - lo) + 1e-6f);
}

}  // namespace aamap
