#include "tracer/environment.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include <fmt/format.h>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include "scene/lat_long.h"

namespace aamap {
namespace {

constexpr float kPi = std::numbers::pi_v<float>;

float luminance(const glm::vec3& c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }

}  // namespace

EnvironmentSampler::EnvironmentSampler(const EnvironmentLight& light)
    : scale_(light.scale), toLocal_(light.toLocal), toWorld_(glm::transpose(light.toLocal)) {
    if (light.map.empty()) return;
    width_ = light.mapWidth;
    height_ = light.mapHeight;
    if (width_ < 1 || height_ < 1 || light.map.size() != static_cast<std::size_t>(width_) * height_)
        throw std::invalid_argument(fmt::format("environment '{}': {} pixels for a {} x {} map", light.name,
                                                light.map.size(), width_, height_));
    map_.resize(light.map.size());
    std::vector<float> weights(map_.size());
    for (int y = 0; y < height_; ++y) {
        // sin(theta) at the row centre: the row's share of the sphere.
        const float sinTheta = std::sin(kPi * (static_cast<float>(y) + 0.5f) / static_cast<float>(height_));
        for (int x = 0; x < width_; ++x) {
            const std::size_t i = static_cast<std::size_t>(y) * width_ + x;
            map_[i] = light.map[i] * scale_;
            weights[i] = std::max(luminance(map_[i]), 0.0f) * sinTheta;
        }
    }
    distribution_.emplace(weights, width_, height_);
}

glm::vec2 EnvironmentSampler::toMap(const glm::vec3& dir) const { return latlong::fromDirection(toLocal_ * dir); }


int EnvironmentSampler::cellIndex(glm::vec2 uv, int& column, int& row) const {
    column = std::clamp(static_cast<int>(uv.x * static_cast<float>(width_)), 0, width_ - 1);
    row = std::clamp(static_cast<int>(uv.y * static_cast<float>(height_)), 0, height_ - 1);
    return row * width_ + column;
}

glm::vec3 EnvironmentSampler::radiance(const glm::vec3& dir) const {
    if (constant()) return scale_;
    int column = 0, row = 0;
    return map_[static_cast<std::size_t>(cellIndex(toMap(dir), column, row))];
}

EnvironmentSampler::Sample EnvironmentSampler::sample(glm::vec2 u) const {
    Sample s{glm::vec3(0.0f, 1.0f, 0.0f), glm::vec3(0.0f), 0.0f};
    if (constant()) return s;
    const Distribution2D::Sample d = distribution_->sample(u);
    const float sinTheta = std::sin(d.point.y * kPi);
    if (!(d.pdf > 0.0f) || !(sinTheta > 0.0f)) return s;
    s.direction = glm::normalize(toWorld_ * latlong::toDirection(d.point, sinTheta));
    s.radiance = map_[static_cast<std::size_t>(d.row) * width_ + d.column];
    // Density over the unit square -> solid angle: d omega = 2 pi^2 sin(theta) du dv.
    s.pdf = d.pdf / (2.0f * kPi * kPi * sinTheta);
    return s;
}

float EnvironmentSampler::pdf(const glm::vec3& dir) const {
    if (constant()) return 0.0f;
    const glm::vec3 local = toLocal_ * dir;
    const glm::vec2 uv = latlong::fromDirection(local);
    // From the direction itself: sin(acos(y)) loses precision towards the poles.
    const float sinTheta = std::sqrt(local.x * local.x + local.z * local.z);
    if (!(sinTheta > 0.0f)) return 0.0f;
    int column = 0, row = 0;
    cellIndex(uv, column, row);
    return distribution_->pdf(column, row) / (2.0f * kPi * kPi * sinTheta);
}

}  // namespace aamap
