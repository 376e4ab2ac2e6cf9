// An environment map that is black but for one small bright cell lights like a sun: the shadow it
// casts on a plane matches the shadow of the directional light with the cell's direction and
// irradiance (radiance times the cell's solid angle), away from the penumbra that the cell's
// finite size adds. Direct mode (m x m map samples with MIS) and Path mode (one map sample per
// vertex) both.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "tests/tracer/material_scenes.h"

namespace aamap {
namespace {

using testing::lookAt;
using testing::renderScene;

constexpr int kMapW = 512, kMapH = 256, kSunColumn = 44, kSunRow = 60;
const glm::vec3 kSunRadiance(20000.0f, 15000.0f, 10000.0f);

// The cell centre's direction by scene/scene.h's convention (identity frame).
glm::vec3 sunDirection() {
    const double theta = (kSunRow + 0.5) / kMapH * std::numbers::pi, phi = (kSunColumn + 0.5) / kMapW * 2.0 * std::numbers::pi;
    return glm::vec3(glm::dvec3(std::sin(theta) * std::sin(phi), std::cos(theta), -std::sin(theta) * std::cos(phi)));
}
double sunSolidAngle() {
    return (2 * std::numbers::pi / kMapW) * (std::cos(kSunRow * std::numbers::pi / kMapH) - std::cos((kSunRow + 1) * std::numbers::pi / kMapH));
}

// A floor with a box floating over it.
Scene floorAndBlocker() {
    testing::SceneBuilder b;
    const auto grey = b.material("grey", glm::vec3(0.5f));
    b.quad({-3, 0, -3}, {0, 0, 6}, {6, 0, 0}, grey);
    b.box({-0.4f, 0.5f, -0.3f}, {0.3f, 0.8f, 0.4f}, grey);
    return std::move(b.scene());
}

Scene withSunMap() {
    Scene s = floorAndBlocker();
    EnvironmentLight env;
    env.name = "sun-map";
    env.mapWidth = kMapW;
    env.mapHeight = kMapH;
    env.map.assign(static_cast<std::size_t>(kMapW) * kMapH, glm::vec3(0.0f));
    env.map[static_cast<std::size_t>(kSunRow) * kMapW + kSunColumn] = kSunRadiance;
    s.environment = env;
    return s;
}

Scene withDirectional() {
    Scene s = floorAndBlocker();
    DirectionalLight d;
    d.name = "sun";
    d.direction = -sunDirection();
    d.irradiance = kSunRadiance * static_cast<float>(sunSolidAngle());
    s.directionalLights.push_back(d);
    return s;
}

// Pixels of the directional render at least `margin` pixels from any lit/shadow boundary, split
// into lit (> 0) and shadowed (0) floor pixels; the map render must match them.
void expectSameShadow(const TraceResult& sun, const TraceResult& map, int size, const char* what) {
    const auto lit = [&](int x, int y) { return sun.image.at(x, y).y > 0.0f; };
    const int margin = 3;
    int litCount = 0, shadowCount = 0;
    std::vector<double> ratio;
    for (int y = margin; y < size - margin; ++y)
        for (int x = margin; x < size - margin; ++x) {
            bool uniform = true;
            for (int dy = -margin; dy <= margin && uniform; ++dy)
                for (int dx = -margin; dx <= margin && uniform; ++dx) uniform = lit(x + dx, y + dy) == lit(x, y);
            if (!uniform) continue;
            const glm::vec3 s = sun.image.at(x, y), m = map.image.at(x, y);
            if (lit(x, y)) {
                ++litCount;
                for (int ch = 0; ch < 3; ++ch) ratio.push_back(m[ch] / s[ch]);
            } else {
                ++shadowCount;
                EXPECT_LT(m.y, 1e-3f) << what << " shadowed pixel " << x << "," << y;
            }
        }
    EXPECT_GT(litCount, size * size / 4) << what;
    EXPECT_GT(shadowCount, size * size / 50) << what;
    const auto [mean, error] = testing::meanError(ratio);
    EXPECT_NEAR(mean, 1.0, 0.01) << what;
    for (double r : ratio) ASSERT_NEAR(r, 1.0, 0.05) << what;  // every lit pixel, not just the mean
}

TEST(EnvironmentShadow, SmallBrightCellShadowsLikeTheEquivalentDirectionalLight) {
    const View view = lookAt({0.5f, 2.5f, 2.5f}, {0, 0, 0}, 55);
    const int size = 64;
    const Scene sun = withDirectional(), map = withSunMap();
    {
        ShadingSettings direct;  // the default light-sample count: one ray per pixel is clean
        expectSameShadow(renderScene(sun, view, direct, size, 1), renderScene(map, view, direct, size, 1), size,
                         "direct");
    }
    {
        ShadingSettings path;
        path.mode = ShadingMode::Path;
        path.maxDepth = 2;  // direct light only, as the directional render's comparison needs none
        expectSameShadow(renderScene(sun, view, path, size, 1), renderScene(map, view, path, size, 1), size, "path");
    }
}

}  // namespace
}  // namespace aamap
