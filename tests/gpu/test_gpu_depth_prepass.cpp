// The G-buffer's depth pre-pass (passes/gbuffer.h) changes no pixel: the nearest surface wins
// whatever the draw order, and where surfaces tie in depth the first triangle of the mesh wins,
// as with a plain GREATER test; the shared positions merge exactly the bit-equal corners.
#include <array>
#include <cstring>
#include <vector>

#include "gpu_fixture.h"
#include "passes/scene_gpu.h"
#include "passes/snapshot.h"
#include "tests/common/test_scenes.h"

namespace aamap::test {
namespace {

// Red (material 0) and green (material 1) squares at the given depths and in the given order.
Scene twoSquares(std::array<std::uint32_t, 2> order, std::array<float, 2> z) {
    Scene scene;
    scene.name = "two squares";
    Material red, green;
    red.kd = {0.8f, 0.0f, 0.0f};
    green.kd = {0.0f, 0.8f, 0.0f};
    scene.materials = {red, green};
    for (int i = 0; i < 2; ++i) addQuadZ(scene, z[order[i]], -1.0f, 1.0f, -1.0f, 1.0f, order[i]);
    PointLight light;
    light.position = {0.2f, 0.1f, 2.0f};
    light.intensity = glm::vec3(10.0f);
    scene.pointLights.push_back(light);
    return scene;
}

View frontView() { return viewDownZ({0.0f, 0.0f, 3.0f}, 30.0f); }

// Pixels where red wins and where green wins; every pixel of the snapshot sees a square.
std::array<int, 2> winners(VulkanContext& context, const Scene& scene) {
    SnapshotRenderer renderer(context, scene);
    SnapshotSettings settings;
    const SnapshotResult r = renderer.render(frontView(), 32, 32, settings);
    std::array<int, 2> count{0, 0};
    for (const glm::vec3& c : r.snapshot.pixels()) {
        EXPECT_TRUE((c.r > 0.0f) != (c.g > 0.0f)) << "one square per pixel, lit";
        ++count[c.r > 0.0f ? 0 : 1];
    }
    return count;
}

class DepthPrepass : public GpuTest {};  // the suite names the feature a failure is in

TEST_F(DepthPrepass, NearestSurfaceWinsInEitherDrawOrder) {
    const int pixels = 48 * 48;
    EXPECT_EQ(winners(context(), twoSquares({0, 1}, {0.0f, 0.5f})), (std::array<int, 2>{0, pixels}));  // green nearer, last
    EXPECT_EQ(winners(context(), twoSquares({1, 0}, {0.0f, 0.5f})), (std::array<int, 2>{0, pixels}));  // green nearer, first
}

TEST_F(DepthPrepass, DepthTiesGoToTheFirstTriangleOfTheMesh) {
    const int pixels = 48 * 48;
    EXPECT_EQ(winners(context(), twoSquares({0, 1}, {0.0f, 0.0f})), (std::array<int, 2>{pixels, 0}));
    EXPECT_EQ(winners(context(), twoSquares({1, 0}, {0.0f, 0.0f})), (std::array<int, 2>{0, pixels}));
}

TEST_F(DepthPrepass, SharedPositionsMergeExactlyTheBitEqualCorners) {
    Scene scene = twoSquares({0, 1}, {0.0f, 0.5f});
    scene.mesh.positions.push_back({-1.0f, -1.0f, 0.0f});  // a copy of a corner: merged, as bits are equal
    scene.mesh.positions.push_back({-0.0f, 0.0f, 0.5f});   // -0 vs +0 below: not merged
    scene.mesh.positions.push_back({0.0f, 0.0f, 0.5f});
    const auto n = static_cast<std::uint32_t>(scene.mesh.positions.size());
    scene.mesh.triangles.push_back({n - 3, n - 2, n - 1});
    scene.mesh.normals.resize(scene.mesh.positions.size(), glm::vec3(0, 0, 1));
    scene.mesh.materialIds.push_back(0);
    scene.mesh.objectIds.push_back(0);
    const passes::SceneGpu sceneGpu(context(), scene);
    ASSERT_TRUE(sceneGpu.sharedPositions());
    const auto positions = sceneGpu.vertexPositions();
    const auto index = sceneGpu.positionIndex();
    ASSERT_EQ(index.size(), positions.size());
    ASSERT_EQ(positions.size(), 15u);
    std::uint32_t distinct = 0;
    for (std::size_t i = 0; i < index.size(); ++i) {
        distinct = std::max(distinct, index[i] + 1);
        for (std::size_t j = 0; j < index.size(); ++j)
            EXPECT_EQ(index[i] == index[j], std::memcmp(&positions[i], &positions[j], sizeof(glm::vec3)) == 0);
    }
    EXPECT_EQ(distinct, 10u);  // 4 + 4 corners, the copied corner merged, -0 and +0 apart
}

}  // namespace
}  // namespace aamap::test
