#include "scene/framing.h"

#include <cmath>
#include <stdexcept>

#include <fmt/format.h>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

namespace aamap {

View lookAtView(glm::vec3 position, glm::vec3 lookAt, glm::vec3 up, float horizontalFovDeg, int width, int height) {
    if (width < 1 || height < 1) throw std::invalid_argument("the image size must be positive");
    const glm::vec3 dir = lookAt - position;
    if (!(glm::length(dir) > 0.0f)) throw std::invalid_argument("position and look_at are the same point");
    if (!(glm::length(up) > 0.0f)) throw std::invalid_argument("up is zero");
    if (glm::length(glm::cross(glm::normalize(dir), glm::normalize(up))) < 1e-6f)
        throw std::invalid_argument("up is parallel to the view direction (look_at - position)");
    if (!(horizontalFovDeg > 0.0f && horizontalFovDeg < 180.0f))
        throw std::invalid_argument(fmt::format("fov {} is outside (0, 180) degrees", horizontalFovDeg));
    View v;
    v.position = position;
    v.direction = glm::normalize(dir);
    v.up = glm::normalize(up);
    v.horizontalFovDeg = horizontalFovDeg;
    const double tanV = std::tan(glm::radians(static_cast<double>(horizontalFovDeg)) * 0.5) * height / width;
    v.verticalFovDeg = static_cast<float>(glm::degrees(2.0 * std::atan(tanV)));
    return v;
}

View framingView(const Bounds& bounds, int width, int height) {
    constexpr float kFov = 45.0f;  // the narrower image side's angle
    const glm::vec3 centre = bounds.centre();
    const float radius = 0.5f * glm::length(bounds.extent());
    const glm::vec3 towardsCamera = glm::normalize(glm::vec3(0.0f, 0.3f, 1.0f));
    const float aspect = static_cast<float>(width) / static_cast<float>(height);
    // Horizontal angle such that the narrower side spans kFov.
    const float tanNarrow = std::tan(glm::radians(kFov) * 0.5f);
    const float tanH = aspect >= 1.0f ? tanNarrow * aspect : tanNarrow;
    const float distance = radius > 0.0f ? radius / std::sin(glm::radians(kFov) * 0.5f) : 1.0f;
    View v = lookAtView(centre + towardsCamera * distance, centre, {0, 1, 0}, glm::degrees(2.0f * std::atan(tanH)),
                        width, height);
    v.name = "framed";
    return v;
}

}  // namespace aamap
