#include "passes/environment_lighting.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include <fmt/format.h>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include "scene/lat_long.h"

namespace aamap::passes {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr float kRegionFraction = 0.25f;      // of the seed pixel's luminance
constexpr double kRegionRadiusDeg = 15.0;     // from the seed pixel's direction
constexpr float kPeakOverMean = 8.0f;         // a region's seed must be this much brighter than the mean

float luminance(const glm::vec3& c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }

}  // namespace

std::array<float, 9> shBasis(const glm::vec3& n) {
    const float x = n.x, y = n.y, z = n.z;
    return {0.282095f,
            0.488603f * y,
            0.488603f * z,
            0.488603f * x,
            1.092548f * x * y,
            1.092548f * y * z,
            0.315392f * (3.0f * z * z - 1.0f),
            1.092548f * x * z,
            0.546274f * (x * x - y * y)};
}

glm::vec3 ambientIrradiance(const std::array<glm::vec3, 9>& irradianceSH, const glm::vec3& n) {
    const std::array<float, 9> y = shBasis(n);
    glm::vec3 e(0.0f);
    for (int i = 0; i < 9; ++i) e += irradianceSH[static_cast<std::size_t>(i)] * y[static_cast<std::size_t>(i)];
    return e;
}

EnvironmentLighting prepareEnvironmentLighting(const EnvironmentLight& env, int maxLights) {
    EnvironmentLighting out;
    // Cosine-lobe convolution per band.
    const float band[9] = {static_cast<float>(kPi),           static_cast<float>(2 * kPi / 3),
                           static_cast<float>(2 * kPi / 3),   static_cast<float>(2 * kPi / 3),
                           static_cast<float>(kPi / 4),       static_cast<float>(kPi / 4),
                           static_cast<float>(kPi / 4),       static_cast<float>(kPi / 4),
                           static_cast<float>(kPi / 4)};
    if (env.map.empty()) {
        // Only Y_0 has a non-zero integral over the sphere: 4 pi Y_0 = 2 sqrt(pi).
        out.irradianceSH[0] = env.scale * static_cast<float>(2.0 * std::sqrt(kPi)) * band[0];
        out.background = env.scale;
        return out;
    }
    const int w = env.mapWidth, h = env.mapHeight;
    const glm::mat3 toWorld = glm::transpose(env.toLocal);
    // World direction of a pixel centre, computed where needed: a large map's directions would
    // take 12 bytes a pixel.
    const auto direction = [&](std::size_t i) {
        const int x = static_cast<int>(i % static_cast<std::size_t>(w)), y = static_cast<int>(i / static_cast<std::size_t>(w));
        return glm::normalize(toWorld * latlong::toDirection({(x + 0.5f) / w, (y + 0.5f) / h}));
    };
    std::vector<glm::vec3> radiance(env.map.size());
    std::vector<float> lum(env.map.size());
    std::vector<float> solidAngle(static_cast<std::size_t>(h));
    double lumTotal = 0.0;  // luminance x solid angle over the sphere
    for (int y = 0; y < h; ++y) {
        solidAngle[static_cast<std::size_t>(y)] = static_cast<float>(latlong::pixelSolidAngle(y, w, h));
        for (int x = 0; x < w; ++x) {
            const std::size_t i = static_cast<std::size_t>(y) * w + x;
            const glm::vec3 c = env.map[i] * env.scale;
            radiance[i] = glm::vec3(std::isfinite(c.x) ? std::max(c.x, 0.0f) : 0.0f,
                                    std::isfinite(c.y) ? std::max(c.y, 0.0f) : 0.0f,
                                    std::isfinite(c.z) ? std::max(c.z, 0.0f) : 0.0f);
            lum[i] = luminance(radiance[i]);
            lumTotal += static_cast<double>(lum[i]) * solidAngle[static_cast<std::size_t>(y)];
        }
    }
    const float meanLum = static_cast<float>(lumTotal / (4.0 * kPi));

    const float cosRadius = static_cast<float>(std::cos(kRegionRadiusDeg * kPi / 180.0));
    std::vector<std::uint8_t> taken(radiance.size(), 0);
    for (int k = 0; k < maxLights; ++k) {
        const auto seed = static_cast<std::size_t>(std::max_element(lum.begin(), lum.end()) - lum.begin());
        // Only what stands out of the sky: an overcast map's brightest patch is no sun, and a
        // hard shadow from it would be wrong; it stays in the ambient term.
        if (!(lum[seed] > kPeakOverMean * meanLum)) break;
        const glm::vec3 seedDirection = direction(seed);
        const float floor = kRegionFraction * lum[seed];
        std::vector<std::size_t> stack{seed};
        taken[seed] = 1;
        glm::dvec3 irradiance(0.0), weighted(0.0);
        while (!stack.empty()) {
            const std::size_t i = stack.back();
            stack.pop_back();
            const double omega = solidAngle[i / static_cast<std::size_t>(w)];
            irradiance += glm::dvec3(radiance[i]) * omega;
            weighted += glm::dvec3(direction(i)) * (static_cast<double>(lum[i]) * omega);
            radiance[i] = glm::vec3(0.0f);  // taken by the light: not in the ambient term
            lum[i] = 0.0f;
            const int x = static_cast<int>(i % static_cast<std::size_t>(w)), y = static_cast<int>(i / static_cast<std::size_t>(w));
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const int ny = y + dy;
                    if (ny < 0 || ny >= h) continue;
                    const int nx = (x + dx + w) % w;
                    const std::size_t j = static_cast<std::size_t>(ny) * w + nx;
                    if (taken[j] || lum[j] < floor || glm::dot(direction(j), seedDirection) < cosRadius) continue;
                    taken[j] = 1;
                    stack.push_back(j);
                }
        }
        DirectionalLight light;
        light.name = fmt::format("{}#{}", env.name.empty() ? "environment" : env.name, k);
        light.direction = -glm::vec3(glm::normalize(weighted));
        light.irradiance = glm::vec3(irradiance);
        out.lights.push_back(light);
    }

    // The residual's SH projection, then the cosine convolution.
    std::array<glm::dvec3, 9> lm{};
    for (std::size_t i = 0; i < radiance.size(); ++i) {
        if (radiance[i] == glm::vec3(0.0f)) continue;
        const double omega = solidAngle[i / static_cast<std::size_t>(w)];
        const std::array<float, 9> y = shBasis(direction(i));
        for (std::size_t c = 0; c < 9; ++c) lm[c] += glm::dvec3(radiance[i]) * (static_cast<double>(y[c]) * omega);
    }
    for (std::size_t c = 0; c < 9; ++c) out.irradianceSH[c] = glm::vec3(lm[c]) * band[c];
    out.background = glm::vec3(lm[0] * (1.0 / (2.0 * std::sqrt(kPi))));  // L_00 Y_0: the mean over 4 pi
    return out;
}

}  // namespace aamap::passes
