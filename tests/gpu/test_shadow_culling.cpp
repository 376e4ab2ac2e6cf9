// The shadow pass's per-face culling is conservative: a triangle left out of a cube face has no
// point inside that face's pyramid (beyond the near plane), so culling never removes a shadow.
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "passes/shadow_cube.h"

namespace aamap::passes {
namespace {

// Whether r (relative to the light) lies in face f's pyramid beyond the near plane.
bool inFace(glm::vec3 r, int f, float nearPlane) {
    const int axis = f >> 1, b = (axis + 1) % 3, c = (axis + 2) % 3;
    const float major = ((f & 1) ? -1.0f : 1.0f) * r[axis];
    return major >= nearPlane && major >= std::fabs(r[b]) && major >= std::fabs(r[c]);
}

TEST(ShadowCulling, CulledTrianglesMissTheFace) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> coord(-3.0f, 3.0f), small(-0.4f, 0.4f);
    std::vector<glm::vec3> positions;
    for (int t = 0; t < 2000; ++t) {
        const glm::vec3 centre(coord(rng), coord(rng), coord(rng));
        for (int k = 0; k < 3; ++k) positions.push_back(centre + glm::vec3(small(rng), small(rng), small(rng)));
    }
    const std::vector<glm::vec3> lights{{0, 0, 0}, {1.0f, -0.5f, 2.0f}};
    const float nearPlane = 0.05f;
    const ShadowCubePass::FaceLists lists = ShadowCubePass::cullPerFace(positions, lights, nearPlane);
    ASSERT_EQ(lists.ranges.size(), 12u);
    std::size_t kept = 0;
    for (std::size_t layer = 0; layer < 12; ++layer) {
        const glm::vec3 light = lights[layer / 6];
        const int face = static_cast<int>(layer % 6);
        std::vector<char> drawn(positions.size() / 3, 0);
        const auto [first, count] = lists.ranges[layer];
        kept += count / 3;
        for (std::uint32_t i = first; i < first + count; i += 3) drawn[lists.indices[i] / 3] = 1;
        for (std::size_t t = 0; t < drawn.size(); ++t) {
            if (drawn[t]) continue;
            // Barycentric samples of the culled triangle: none may be inside the face.
            for (int a = 0; a <= 8; ++a) {
                for (int b = 0; a + b <= 8; ++b) {
                    const float u = a / 8.0f, v = b / 8.0f;
                    const glm::vec3 p = (1.0f - u - v) * positions[3 * t] + u * positions[3 * t + 1] + v * positions[3 * t + 2];
                    ASSERT_FALSE(inFace(p - light, face, nearPlane)) << "triangle " << t << " culled from layer " << layer;
                }
            }
        }
    }
    // And it culls: most small triangles touch one or two of a light's six faces.
    EXPECT_LT(kept, 2u * 2000u * 2u);
    EXPECT_GE(kept, 2000u * 2u);
}

}  // namespace
}  // namespace aamap::passes
