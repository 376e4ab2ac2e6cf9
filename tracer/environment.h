#pragma once
// The environment (scene/scene.h EnvironmentLight) as the integrator samples it. A constant sky
// is left to BSDF sampling: for constant radiance the cosine (and Phong) lobe is already the
// ideal importance, so there is nothing to gain from light samples. A map is importance-sampled
// with a piecewise-constant distribution over its pixels, weighted by luminance times sin(theta)
// (the solid angle of a lat-long row), and combined with BSDF sampling by MIS.
//
// Lookups are nearest-pixel, so the radiance is exactly constant over each cell the distribution
// samples from: the light-sample estimator's luminance is then constant over the map.
#include <optional>
#include <vector>

#include <glm/mat3x3.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "scene/scene.h"
#include "tracer/distribution_2d.h"

namespace aamap {

class EnvironmentSampler {
public:
    // Throws std::invalid_argument for a map whose size does not match its pixels.
    explicit EnvironmentSampler(const EnvironmentLight& light);

    // No map: radiance is scale everywhere, and sample() is never needed.
    bool constant() const { return !distribution_.has_value(); }
    // Radiance arriving from unit world direction `dir` (pointing away from the scene).
    glm::vec3 radiance(const glm::vec3& dir) const;

    struct Sample {
        glm::vec3 direction;  // unit, world, towards the sky
        glm::vec3 radiance;
        float pdf;            // solid angle; 0: no sample (a black map, or a pole)
    };
    // A map direction by importance; u in [0,1)^2. Only for !constant().
    Sample sample(glm::vec2 u) const;
    // The solid-angle density sample() has for `dir`; 0 for a constant environment.
    float pdf(const glm::vec3& dir) const;

    // Map coordinates of a world direction (the Mitsuba convention, scene/scene.h).
    glm::vec2 toMap(const glm::vec3& dir) const;

    // The map and its distribution as sample() reads them (only for !constant()).
    int width() const { return width_; }
    int height() const { return height_; }
    const std::vector<glm::vec3>& map() const { return map_; }
    const Distribution2D& distribution() const { return *distribution_; }
    const glm::mat3& toWorld() const { return toWorld_; }

private:
    int cellIndex(glm::vec2 uv, int& column, int& row) const;

    glm::vec3 scale_;
    glm::mat3 toLocal_, toWorld_;
    int width_ = 0, height_ = 0;
    std::vector<glm::vec3> map_;  // scale applied
    std::optional<Distribution2D> distribution_;
};

}  // namespace aamap
