// The geometric aamap: the GPU edge pass against the CPU reference of the rule
// (glsl/shared/geometric_edges.h), and a crease between two surfaces of equal colour that the
// geometric map flags and the luminance map does not.
#include <algorithm>
#include <cmath>
#include <random>
#include <string>

#include <glm/geometric.hpp>

#include "gpu_fixture.h"
#include "glsl/shared/geometric_edges.h"
#include "passes/cpu_geometric.h"
#include "passes/geometric_aamap.h"
#include "passes/snapshot.h"

namespace aamap::test {
namespace {

// Patches of 5 x 4 texels, each a plane in inverse depth (1/z affine in x, y: a planar surface
// seen in perspective) with its own normal and ids, some uncovered. Values stay far from the
// rule's thresholds so that float rounding cannot decide differently on the two sides.
cpu::GeometryImages patchwork(int w, int h, std::uint32_t seed) {
    const glm::vec3 normals[] = {{0, 0, 1}, {0, 0.28f, 0.96f}, {0.6f, 0, 0.8f}, {1, 0, 0}};
    std::mt19937 rng(seed);
    cpu::GeometryImages g{Image<glm::vec4>(w, h), Image<glm::vec4>(w, h)};
    const int px = (w + 4) / 5, py = (h + 3) / 4;
    for (int j = 0; j < py; ++j)
        for (int i = 0; i < px; ++i) {
            const bool covered = rng() % 6 != 0;
            const glm::vec3 n = normals[rng() % 4];
            const float a = 0.1f * static_cast<float>(1 + rng() % 4);  // jumps of >= 25 %
            const float bx = 1e-3f * static_cast<float>(rng() % 3), by = 1e-3f * static_cast<float>(rng() % 3);
            const glm::vec4 ids(static_cast<float>(rng() % 2), static_cast<float>(rng() % 3), 0, 0);
            for (int y = j * 4; y < std::min(h, j * 4 + 4); ++y)
                for (int x = i * 5; x < std::min(w, i * 5 + 5); ++x) {
                    const float inverseDepth = a + bx * static_cast<float>(x) + by * static_cast<float>(y);
                    g.normalDepth.at(x, y) = covered ? glm::vec4(n, 1.0f / inverseDepth) : glm::vec4(0.0f);
                    g.ids.at(x, y) = covered ? ids : glm::vec4(0.0f);
                }
        }
    return g;
}

class GeometricTest : public GpuTest {};

TEST_F(GeometricTest, EdgePassMatchesCpuReference) {
    passes::GpuGeometricEdges gpu(context());
    for (auto [w, h] : {std::pair{61, 37}, std::pair{1, 1}, std::pair{3, 7}, std::pair{200, 3}}) {
        const cpu::GeometryImages g = patchwork(w, h, static_cast<std::uint32_t>(w * 31 + h));
        const ImageGrey expected = cpu::geometricEdges(g);
        const ImageGrey got = gpu.edges(g);
        EXPECT_TRUE(got.pixels() == expected.pixels()) << w << "x" << h;
        if (w * h > 100) {  // a real mix of edges and flat texels
            const auto edges = std::count_if(expected.pixels().begin(), expected.pixels().end(),
                                             [](float v) { return v > 0.0f; });
            EXPECT_GT(edges, w * h / 10);
            EXPECT_LT(edges, w * h * 9 / 10);
        }
        ImageGrey laplacian(w, h);
        std::mt19937 rng(7);
        for (float& v : laplacian.pixels()) v = static_cast<float>(rng() % 1000) * 0.006f;  // 0 .. 6
        EXPECT_TRUE(gpu.edges(g, &laplacian).pixels() == cpu::maxEdges(expected, laplacian).pixels()) << w << "x" << h;
    }
}

TEST_F(GeometricTest, EachRuleFiresAlone) {
    // Two halves that differ in one attribute only; everything else equal and planar.
    auto split = [](auto change) {
        cpu::GeometryImages g{Image<glm::vec4>(8, 4, glm::vec4(0, 0, 1, 2.0f)), Image<glm::vec4>(8, 4, glm::vec4(0))};
        for (int y = 0; y < 4; ++y)
            for (int x = 4; x < 8; ++x) change(g.normalDepth.at(x, y), g.ids.at(x, y));
        return g;
    };
    const float edge = static_cast<float>(GEOMETRIC_EDGE_VALUE);
    passes::GpuGeometricEdges gpu(context());
    const std::pair<std::string, cpu::GeometryImages> cases[] = {
        {"object", split([](glm::vec4&, glm::vec4& id) { id.x = 1; })},
        {"material", split([](glm::vec4&, glm::vec4& id) { id.y = 5; })},
        {"normal 40 deg", split([](glm::vec4& nd, glm::vec4&) { nd = glm::vec4(0.643f, 0, 0.766f, nd.w); })},
        {"depth x2", split([](glm::vec4& nd, glm::vec4&) { nd.w = 4.0f; })},
        {"coverage", split([](glm::vec4& nd, glm::vec4&) { nd = glm::vec4(0.0f); })},
    };
    for (const auto& [name, g] : cases) {
        const ImageGrey e = gpu.edges(g);
        EXPECT_TRUE(e.pixels() == cpu::geometricEdges(g).pixels()) << name;
        for (int y = 0; y < 4; ++y) {
            EXPECT_EQ(e.at(3, y), edge) << name;
            EXPECT_EQ(e.at(0, y), 0.0f) << name;
            EXPECT_EQ(e.at(7, y), 0.0f) << name;
        }
    }
    // Below the thresholds: a 20 degree crease and a 2 % depth step are not edges.
    const cpu::GeometryImages soft = split([](glm::vec4& nd, glm::vec4&) { nd = glm::vec4(0.342f, 0, 0.940f, 2.04f); });
    EXPECT_EQ(cpu::geometricEdges(soft).at(3, 1), 0.0f);
    EXPECT_EQ(gpu.edges(soft).at(3, 1), 0.0f);
}

// A ridge of two planes with equal emission (no lights): one colour everywhere, so the luminance
// Laplacian is exactly zero, while the normals turn by 90 degrees along the crease.
Scene equalColourRidge() {
    Scene s;
    Material m;
    m.name = "glow";
    m.kd = glm::vec3(0.0f);
    m.ke = glm::vec3(0.5f);
    s.materials.push_back(m);
    TriangleMesh& mesh = s.mesh;
    auto quad = [&](glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 d, glm::vec3 n) {
        const auto base = static_cast<std::uint32_t>(mesh.positions.size());
        for (const glm::vec3& p : {a, b, c, d}) {
            mesh.positions.push_back(p);
            mesh.normals.push_back(n);
        }
        mesh.triangles.push_back({base, base + 1, base + 2});
        mesh.triangles.push_back({base, base + 2, base + 3});
        for (int i = 0; i < 2; ++i) {
            mesh.materialIds.push_back(0);
            mesh.objectIds.push_back(0);  // one object, one material: only the normals differ
        }
    };
    const float L = 100.0f;
    // z = x for x < 0 and z = -x for x > 0: the crease runs along y through the origin.
    quad({-L, -L, -L}, {0, -L, 0}, {0, L, 0}, {-L, L, -L}, glm::normalize(glm::vec3(-1, 0, 1)));
    quad({0, -L, 0}, {L, -L, -L}, {L, L, -L}, {0, L, 0}, glm::normalize(glm::vec3(1, 0, 1)));
    View v;
    v.position = {0, 0, 5};
    v.direction = {0, 0, -1};
    v.horizontalFovDeg = v.verticalFovDeg = 60;
    s.views.push_back(v);
    return s;
}

TEST_F(GeometricTest, CreaseOfEqualColourIsFlaggedOnlyByTheGeometricMap) {
    const Scene scene = equalColourRidge();
    SnapshotRenderer renderer(context(), scene);
    SnapshotSettings settings;
    const int W = 48, H = 32;
    settings.map = passes::AamapSource::Luminance;
    const SnapshotResult luminance = renderer.render(scene.views[0], W, H, settings);
    settings.map = passes::AamapSource::Geometric;
    const SnapshotResult geometric = renderer.render(scene.views[0], W, H, settings);
    settings.map = passes::AamapSource::Combined;
    const SnapshotResult combined = renderer.render(scene.views[0], W, H, settings);

    // The luminance Snapshot never rasterises the geometry: the graph culls it and says why.
    const std::size_t cullSection = luminance.explain.find("cull");
    ASSERT_NE(cullSection, std::string::npos) << luminance.explain;
    const std::string culled = luminance.explain.substr(cullSection);
    EXPECT_NE(culled.find("geometry_buffer"), std::string::npos) << luminance.explain;
    for (const PassTiming& p : luminance.passTimes) EXPECT_NE(p.pass, "geometry_buffer");
    bool rasterised = false;
    for (const PassTiming& p : geometric.passTimes) rasterised = rasterised || p.pass == "geometry_buffer";
    EXPECT_TRUE(rasterised);

    for (float v : luminance.aamap.pixels()) EXPECT_EQ(v, 0.0f);  // one colour: nothing to see
    for (int y = 0; y < H; ++y) {
        EXPECT_GT(geometric.aamap.at(W / 2 - 1, y) + geometric.aamap.at(W / 2, y), 0.5f) << "row " << y;
        EXPECT_EQ(geometric.aamap.at(2, y), 0.0f) << "row " << y;  // planar: no edge away from the crease
        EXPECT_EQ(geometric.aamap.at(W - 3, y), 0.0f) << "row " << y;
        for (int x = 0; x < W; ++x)
            EXPECT_GE(combined.aamap.at(x, y), std::max(geometric.aamap.at(x, y), luminance.aamap.at(x, y)) - 1e-6f);
    }
    EXPECT_FALSE(geometric.edges.empty());
    EXPECT_TRUE(geometric.laplacian.empty());
}

}  // namespace
}  // namespace aamap::test
