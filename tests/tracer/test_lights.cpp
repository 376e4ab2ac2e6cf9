#include <vector>

#include <gtest/gtest.h>

#include "tests/tracer/scene_builder.h"
#include "tracer/embree_scene.h"
#include "tracer/lights.h"

namespace aamap {
namespace {

// A light made of `strips` quads side by side along x with widths 1, 2, 3, ...: samples must land
// in each strip in proportion to its area, whichever triangle-selection path the count takes.
void checkAreaSampling(int strips) {
    testing::SceneBuilder b;
    std::vector<float> edges{0.0f};
    for (int i = 0; i < strips; ++i) edges.push_back(edges.back() + static_cast<float>(i + 1));
    AreaLight light;
    light.radiance = glm::vec3(1.0f);
    const auto mat = b.material("light", glm::vec3(0.0f), glm::vec3(1.0f));
    for (int i = 0; i < strips; ++i) {
        // Faces -y: cross(+x, +z).
        const auto tris = b.quad({edges[i], 0, 0}, {edges[i + 1] - edges[i], 0, 0}, {0, 0, 1}, mat);
        light.triangles.insert(light.triangles.end(), tris.begin(), tris.end());
    }
    const EmbreeScene geometry(b.scene());
    const AreaLightSampler sampler(light, geometry);
    EXPECT_NEAR(sampler.area(), edges.back(), 1e-4);

    // Fine in u.x, which picks the triangle: each triangle gets a whole number of columns.
    constexpr int kColumns = 4096, kRows = 4;
    std::vector<int> counts(static_cast<std::size_t>(strips), 0);
    for (int y = 0; y < kRows; ++y)
        for (int x = 0; x < kColumns; ++x) {
            const LightPoint p = sampler.sample({(x + 0.5f) / kColumns, (y + 0.5f) / kRows});
            ASSERT_EQ(p.position.y, 0.0f);
            ASSERT_GE(p.position.z, 0.0f);
            ASSERT_LE(p.position.z, 1.0f);
            ASSERT_EQ(p.normal, glm::vec3(0, -1, 0));
            int strip = 0;
            while (strip + 1 < strips && p.position.x >= edges[strip + 1]) ++strip;
            ASSERT_GE(p.position.x, 0.0f);
            ASSERT_LE(p.position.x, edges.back());
            ++counts[static_cast<std::size_t>(strip)];
        }
    for (int i = 0; i < strips; ++i) {
        const double expected = kColumns * kRows * (i + 1) / static_cast<double>(edges.back());
        EXPECT_NEAR(counts[static_cast<std::size_t>(i)], expected, 4.0 * kRows) << "strip " << i;
    }
}

TEST(AreaLightSampler, UniformByAreaFewTriangles) { checkAreaSampling(3); }
TEST(AreaLightSampler, UniformByAreaManyTriangles) { checkAreaSampling(12); }

}  // namespace
}  // namespace aamap
