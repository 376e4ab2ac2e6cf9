#pragma once
// The one camera convention shared by the Snapshot raster and the tracer, so that pixel (x, y)
// means the same ray on both sides. Film coordinates (u, v) are in [0,1]^2 with v = 0 at the top
// row; pixel (x, y) covers [x, x+1] x [y, y+1] / (width, height).
#include <glm/geometric.hpp>
#include <glm/mat4x4.hpp>
#include <glm/trigonometric.hpp>
#include <glm/vec3.hpp>

#include "scene/scene.h"

namespace aamap {

struct PinholeCamera {
    glm::vec3 origin{0.0f};
    glm::vec3 forward{0, 0, -1};  // unit view direction
    glm::vec3 right{1, 0, 0};     // unit, image +x
    glm::vec3 up{0, 1, 0};        // unit, image -y (up on screen)
    float tanHalfH = 1.0f;        // tan(vh/2)
    float tanHalfV = 1.0f;        // tan(vv/2)
    float shiftX = 0.0f, shiftY = 0.0f;  // Radiance -vs/-vl, in fractions of the view

    static PinholeCamera fromView(const View& view) {
        PinholeCamera c;
        c.origin = view.position;
        c.forward = glm::normalize(view.direction);
        c.right = glm::normalize(glm::cross(c.forward, view.up));
        c.up = glm::cross(c.right, c.forward);
        c.tanHalfH = std::tan(glm::radians(view.horizontalFovDeg) * 0.5f);
        c.tanHalfV = std::tan(glm::radians(view.verticalFovDeg) * 0.5f);
        c.shiftX = view.shiftX;
        c.shiftY = view.shiftY;
        return c;
    }

    // Unnormalised direction through film point (u, v).
    glm::vec3 direction(float u, float v) const {
        const float sx = (2.0f * (u + shiftX) - 1.0f) * tanHalfH;
        const float sy = (1.0f - 2.0f * (v - shiftY)) * tanHalfV;
        return forward + sx * right + sy * up;
    }

    glm::mat4 viewMatrix() const;  // world -> camera (right-handed, camera looks down -z)
    // Vulkan clip space (y down, depth 0..1) with the same (possibly shifted) frustum as direction().
    glm::mat4 projectionMatrix(float nearPlane, float farPlane) const;
};

inline glm::mat4 PinholeCamera::viewMatrix() const {
    glm::mat4 m(1.0f);
    m[0][0] = right.x;    m[1][0] = right.y;    m[2][0] = right.z;
    m[0][1] = up.x;       m[1][1] = up.y;       m[2][1] = up.z;
    m[0][2] = -forward.x; m[1][2] = -forward.y; m[2][2] = -forward.z;
    m[3][0] = -glm::dot(right, origin);
    m[3][1] = -glm::dot(up, origin);
    m[3][2] = glm::dot(forward, origin);
    return m;
}

inline glm::mat4 PinholeCamera::projectionMatrix(float n, float f) const {
    // Camera-space point (x, y, z), z < 0. Screen x in [-1,1] left to right maps to
    // (x / -z) in [(-1+2sX) tanH, (1+2sX) tanH]; Vulkan NDC y points down, so screen up is -y.
    const float cx = 2.0f * shiftX;  // centre offset in NDC units
    const float cy = 2.0f * shiftY;
    glm::mat4 p(0.0f);
    p[0][0] = 1.0f / tanHalfH;
    p[2][0] = cx;   // x_ndc = (x/(-z))/tanH - cx  (x_clip gains cx*z, w = -z)
    p[1][1] = -1.0f / tanHalfV;
    p[2][1] = -cy;  // y_ndc = -(y/(-z))/tanV - cy  (v grows downwards, as in direction())
    p[2][2] = f / (n - f);
    p[3][2] = n * f / (n - f);
    p[2][3] = -1.0f;
    return p;
}

}  // namespace aamap
