// The Snapshot's environment preparation on the CPU (passes/environment_lighting.h): the SH
// ambient term reproduces the irradiance of skies that order-2 harmonics hold exactly (constant,
// linear in the direction), and the brightest region becomes a directional light with the
// region's direction and irradiance, leaving nothing of it in the ambient term.
#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "passes/environment_lighting.h"
#include "scene/lat_long.h"

namespace aamap::passes {
namespace {

constexpr float kPi = std::numbers::pi_v<float>;

TEST(EnvironmentLighting, ConstantSkyGivesPiLEverywhereAndNoLights) {
    EnvironmentLight env;
    env.scale = {0.5f, 1.0f, 2.0f};
    const EnvironmentLighting e = prepareEnvironmentLighting(env, 2);
    EXPECT_TRUE(e.lights.empty());
    for (const glm::vec3 n : {glm::vec3(0, 1, 0), glm::vec3(0, 0, -1), glm::normalize(glm::vec3(1, -2, 3))}) {
        const glm::vec3 got = ambientIrradiance(e.irradianceSH, n);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], kPi * env.scale[c], 1e-4f * kPi * env.scale[c]);
    }
}

// L(w) = c0 + c . w (in world space, any frame rotation): E(n) = pi c0 + (2 pi / 3) c . n exactly
// for order <= 1, so the 9 coefficients hold it up to the map's discretisation.
TEST(EnvironmentLighting, LinearSkyGivesItsExactIrradiance) {
    const int w = 128, h = 64;
    EnvironmentLight env;
    env.mapWidth = w;
    env.mapHeight = h;
    env.toLocal = glm::mat3(glm::vec3(0, 0, 1), glm::vec3(1, 0, 0), glm::vec3(0, 1, 0));  // a rotation
    const glm::mat3 toWorld = glm::transpose(env.toLocal);
    const float c0 = 2.0f;
    const glm::vec3 c(0.3f, 0.5f, -0.4f);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const glm::vec3 d = toWorld * latlong::toDirection({(x + 0.5f) / w, (y + 0.5f) / h});
            env.map.push_back(glm::vec3(c0 + glm::dot(c, d)));
        }
    // Its brightest patch does not stand out (2.7 over a mean of 2): no light even when asked.
    const EnvironmentLighting e = prepareEnvironmentLighting(env, 4);
    EXPECT_TRUE(e.lights.empty());
    for (const glm::vec3 n : {glm::vec3(0, 1, 0), glm::vec3(1, 0, 0), glm::normalize(glm::vec3(-1, 2, -3))}) {
        const float want = kPi * c0 + (2.0f * kPi / 3.0f) * glm::dot(c, n);
        EXPECT_NEAR(ambientIrradiance(e.irradianceSH, n).x, want, 2e-3f * want);
    }
}

TEST(EnvironmentLighting, BrightestCellBecomesADirectionalLightAndLeavesTheAmbient) {
    const int w = 256, h = 128, column = 40, row = 30;
    EnvironmentLight env;
    env.name = "sky";
    env.mapWidth = w;
    env.mapHeight = h;
    env.scale = glm::vec3(2.0f);
    env.map.assign(static_cast<std::size_t>(w) * h, glm::vec3(0.01f));
    env.map[static_cast<std::size_t>(row) * w + column] = glm::vec3(5000.0f, 4000.0f, 3000.0f);
    const EnvironmentLighting e = prepareEnvironmentLighting(env, 1);
    ASSERT_EQ(e.lights.size(), 1u);
    const glm::vec3 toSun = latlong::toDirection({(column + 0.5f) / w, (row + 0.5f) / h});
    EXPECT_NEAR(glm::dot(-e.lights[0].direction, toSun), 1.0f, 1e-6f);
    const float omega = static_cast<float>(latlong::pixelSolidAngle(row, w, h));
    EXPECT_NEAR(e.lights[0].irradiance.x, 2.0f * 5000.0f * omega, 1e-4f * 2.0f * 5000.0f * omega);
    EXPECT_EQ(e.lights[0].name, "sky#0");
    // What remains is the dim sky: E = pi * 0.02 (less the cell, negligible).
    const glm::vec3 ambient = ambientIrradiance(e.irradianceSH, {0, 1, 0});
    EXPECT_NEAR(ambient.x, kPi * 0.02f, 2e-3f * kPi * 0.02f);
    // No lights requested: the cell stays in the ambient term, which then sees it.
    const EnvironmentLighting all = prepareEnvironmentLighting(env, 0);
    EXPECT_TRUE(all.lights.empty());
    EXPECT_GT(ambientIrradiance(all.irradianceSH, toSun).x, 10.0f * ambient.x);
}

}  // namespace
}  // namespace aamap::passes
