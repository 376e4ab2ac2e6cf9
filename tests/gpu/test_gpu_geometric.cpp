// The geometric aamap: the GPU edge pass against the CPU reference of the rule
// (glsl/shared/geometric_edges.h), a crease between two surfaces of equal colour that the
// geometric map flags and the luminance map does not, a shadow boundary on a floor of one albedo
// (the occlusion mask), and alpha cut-outs (the G-buffer's alpha test in the geometry raster).
#include <algorithm>
#include <cmath>
#include <random>
#include <string>

#include <glm/geometric.hpp>

#include "tests/common/temp_dir.h"
#include "../scene/textured_quad_files.h"
#include "gpu_fixture.h"
#include "glsl/shared/geometric_edges.h"
#include "passes/cpu_geometric.h"
#include "passes/geometric_aamap.h"
#include "passes/snapshot.h"
#include "scene/camera.h"
#include "scene/gltf_loader.h"

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
            // Occlusion mask halves: mostly none, else a low or a high bit (light 3 or light 20).
            const std::uint32_t mask = rng() % 3 == 0 ? (rng() % 2 ? 1u << 3 : 1u << 20) : 0u;
            const glm::vec4 ids(static_cast<float>(rng() % 2), static_cast<float>(rng() % 3),
                                static_cast<float>(mask & 0xffffu), static_cast<float>(mask >> 16));
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
        {"occlusion mask, low half", split([](glm::vec4&, glm::vec4& id) { id.z = 1; })},
        {"occlusion mask, high half", split([](glm::vec4&, glm::vec4& id) { id.w = 32768; })},
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

// An axis-aligned box quad by quad (outward normals), or the floor: one material, so the albedo is
// equal everywhere and only object ids and the occlusion mask tell the surfaces apart.
void addQuad(Scene& s, glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 d, std::uint32_t object) {
    const auto base = static_cast<std::uint32_t>(s.mesh.positions.size());
    const glm::vec3 n = glm::normalize(glm::cross(b - a, c - a));
    for (const glm::vec3& p : {a, b, c, d}) {
        s.mesh.positions.push_back(p);
        s.mesh.normals.push_back(n);
    }
    s.mesh.triangles.insert(s.mesh.triangles.end(), {{base, base + 1, base + 2}, {base, base + 2, base + 3}});
    s.mesh.materialIds.insert(s.mesh.materialIds.end(), 2, 0u);
    s.mesh.objectIds.insert(s.mesh.objectIds.end(), 2, object);
}

constexpr glm::vec3 kBoxLo{-0.5f, 0.0f, -0.5f}, kBoxHi{0.5f, 1.0f, 0.5f};
constexpr glm::vec3 kLight{-1.5f, 3.0f, -1.0f};

Scene boxOnFloor() {
    Scene s;
    Material m;
    m.name = "grey";
    m.kd = glm::vec3(0.5f);
    s.materials.push_back(m);
    const float F = 6.0f;
    addQuad(s, {-F, 0, F}, {F, 0, F}, {F, 0, -F}, {-F, 0, -F}, 0);  // floor, facing +y
    const glm::vec3 l = kBoxLo, h = kBoxHi;
    addQuad(s, {l.x, h.y, h.z}, {h.x, h.y, h.z}, {h.x, h.y, l.z}, {l.x, h.y, l.z}, 1);  // top
    addQuad(s, {l.x, l.y, h.z}, {h.x, l.y, h.z}, {h.x, h.y, h.z}, {l.x, h.y, h.z}, 1);  // +z
    addQuad(s, {h.x, l.y, l.z}, {l.x, l.y, l.z}, {l.x, h.y, l.z}, {h.x, h.y, l.z}, 1);  // -z
    addQuad(s, {h.x, l.y, h.z}, {h.x, l.y, l.z}, {h.x, h.y, l.z}, {h.x, h.y, h.z}, 1);  // +x
    addQuad(s, {l.x, l.y, l.z}, {l.x, l.y, h.z}, {l.x, h.y, h.z}, {l.x, h.y, l.z}, 1);  // -x
    PointLight light;
    light.name = "bulb";
    light.position = kLight;
    light.intensity = glm::vec3(20.0f);
    s.pointLights.push_back(light);
    View v;
    v.position = {0.5f, 4.0f, 5.0f};
    v.direction = glm::normalize(glm::vec3(0.8f, 0.0f, 0.8f) - v.position);
    v.up = {0, 1, 0};
    v.horizontalFovDeg = v.verticalFovDeg = 60;
    s.views.push_back(v);
    return s;
}

// Slab test: does the segment o + t d, t in (0, 1), pass through the box?
bool segmentHitsBox(glm::vec3 o, glm::vec3 d) {
    float t0 = 0.0f, t1 = 1.0f;
    for (int a = 0; a < 3; ++a) {
        if (std::fabs(d[a]) < 1e-12f) {
            if (o[a] < kBoxLo[a] || o[a] > kBoxHi[a]) return false;
            continue;
        }
        float ta = (kBoxLo[a] - o[a]) / d[a], tb = (kBoxHi[a] - o[a]) / d[a];
        if (ta > tb) std::swap(ta, tb);
        t0 = std::max(t0, ta);
        t1 = std::min(t1, tb);
    }
    return t0 < t1;
}

// What the camera ray through pixel (x, y) sees: -1 the box (or nothing), 0 lit floor, 1 shadowed
// floor (the analytic shadow of the box from the point light).
int floorClass(const PinholeCamera& camera, int x, int y, int w, int h) {
    const glm::vec3 d = camera.direction((static_cast<float>(x) + 0.5f) / static_cast<float>(w),
                                         (static_cast<float>(y) + 0.5f) / static_cast<float>(h));
    if (d.y >= 0.0f) return -1;
    const glm::vec3 q = camera.origin - (camera.origin.y / d.y) * d;
    if (std::max(std::fabs(q.x), std::fabs(q.z)) > 6.0f) return -1;
    if (segmentHitsBox(camera.origin, q - camera.origin)) return -1;  // the box hides the floor
    return segmentHitsBox(q, kLight - q) ? 1 : 0;
}

TEST_F(GeometricTest, ShadowBoundaryOnFloorOfOneAlbedoIsAnEdge) {
    const Scene scene = boxOnFloor();
    SnapshotRenderer renderer(context(), scene);
    SnapshotSettings settings;
    settings.scale = 1.0f;  // edges at render resolution, one camera ray per pixel to classify
    settings.map = passes::AamapSource::Geometric;
    const int W = 64, H = 64;
    const SnapshotResult shadowed = renderer.render(scene.views[0], W, H, settings);
    settings.shadows.enabled = false;
    const SnapshotResult unshadowed = renderer.render(scene.views[0], W, H, settings);
    ASSERT_EQ(shadowed.edges.width(), W);
    EXPECT_EQ(shadowed.shadowCubeMaps, 1);
    EXPECT_NE(shadowed.explain.find("shadow occlusion mask"), std::string::npos) << shadowed.explain;
    EXPECT_EQ(unshadowed.explain.find("shadow occlusion mask"), std::string::npos) << unshadowed.explain;

    const PinholeCamera camera = PinholeCamera::fromView(scene.views[0]);
    Image<int> cls(W, H);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) cls.at(x, y) = floorClass(camera, x, y, W, H);
    // Within r pixels: all floor of one class (interior), or all floor with both classes (boundary).
    auto classes = [&](int x, int y, int r) {
        int seen = 0;  // bit 0 lit, bit 1 shadowed, bit 2 not floor
        for (int j = std::max(y - r, 0); j <= std::min(y + r, H - 1); ++j)
            for (int i = std::max(x - r, 0); i <= std::min(x + r, W - 1); ++i)
                seen |= cls.at(i, j) < 0 ? 4 : 1 << cls.at(i, j);
        return seen;
    };
    int interior[2] = {0, 0}, boundary = 0;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const int near = classes(x, y, 2);
            if (near == 1 || near == 2) {  // well inside the lit or the shadowed floor
                ++interior[near - 1];
                EXPECT_EQ(shadowed.edges.at(x, y), 0.0f) << "interior " << near << " at " << x << "," << y;
            } else if (near == 3 && cls.at(x, y) >= 0) {
                const int crossing = classes(x, y, 1);
                float flagged = 0.0f;  // anywhere within 2 pixels: the shadow map's texels and bias move it
                for (int j = std::max(y - 2, 0); j <= std::min(y + 2, H - 1); ++j)
                    for (int i = std::max(x - 2, 0); i <= std::min(x + 2, W - 1); ++i)
                        flagged = std::max(flagged, shadowed.edges.at(i, j));
                const float control = unshadowed.edges.at(x, y);
                if (crossing == 3) {  // the analytic boundary runs through this pixel's neighbours
                    ++boundary;
                    EXPECT_EQ(flagged, static_cast<float>(GEOMETRIC_EDGE_VALUE)) << "boundary at " << x << "," << y;
                }
                EXPECT_EQ(control, 0.0f) << "without shadows, the floor near " << x << "," << y << " is one surface";
            }
        }
    EXPECT_GT(interior[0], 200);
    EXPECT_GT(interior[1], 20);
    EXPECT_GT(boundary, 10);
}

// A floor-facing wall behind the alpha-masked quad of tests/scene/textured_quad_files.h.
void addWall(Scene& scene, float h, float z) {
    Material m;
    m.name = "wall";
    m.kd = glm::vec3(0.5f);
    const auto material = static_cast<std::uint32_t>(scene.materials.size());
    scene.materials.push_back(m);
    const auto base = static_cast<std::uint32_t>(scene.mesh.positions.size());
    scene.mesh.positions.insert(scene.mesh.positions.end(), {{-h, -h, z}, {h, -h, z}, {h, h, z}, {-h, h, z}});
    scene.mesh.normals.insert(scene.mesh.normals.end(), 4, glm::vec3(0, 0, 1));
    scene.mesh.uvs.insert(scene.mesh.uvs.end(), 4, glm::vec2(0.0f));
    scene.mesh.triangles.insert(scene.mesh.triangles.end(), {{base, base + 1, base + 2}, {base, base + 2, base + 3}});
    scene.mesh.materialIds.insert(scene.mesh.materialIds.end(), 2, material);
    scene.mesh.objectIds.insert(scene.mesh.objectIds.end(), 2, material);
}

TEST_F(GeometricTest, AlphaCutOutsAreHolesInTheGeometricMap) {
    View view;
    view.position = {0, 0, 3};
    view.direction = {0, 0, -1};
    view.up = {0, 1, 0};
    view.horizontalFovDeg = view.verticalFovDeg = 60;
    const PinholeCamera camera = PinholeCamera::fromView(view);
    const int w = 96, h = 96;
    SnapshotSettings settings;
    settings.scale = 1.0f;
    settings.map = passes::AamapSource::Geometric;
    // lit: a light at the eye with shadows on (the textured and shadowed variant): the cut-out
    // casts a cut-out shadow that the eye cannot see, so the map must not change.
    auto render = [&](const std::string& alphaMode, bool lit) {
        TempDir dir;
        writePng(dir, "tex.png", 16, holeTexture(16, true));
        Scene scene = loadGltf(writeQuadGltf(dir, "tex.png", alphaMode));
        addWall(scene, 6.0f, -1.0f);
        if (lit) {
            PointLight light;
            light.name = "bulb";
            light.position = view.position;
            light.intensity = glm::vec3(30.0f);
            scene.pointLights.push_back(light);
        }
        SnapshotRenderer renderer(context(), scene);
        return renderer.render(view, w, h, settings);
    };
    const SnapshotResult masked = render("MASK", false), opaque = render("OPAQUE", false);
    const SnapshotResult maskedLit = render("MASK", true);
    ASSERT_EQ(masked.edges.width(), w);
    EXPECT_NE(maskedLit.explain.find("shadow occlusion mask"), std::string::npos) << maskedLit.explain;
    // Where the camera ray meets the quad's plane z = 0 (the quad spans [-1, 1]^2, hole [-0.5, 0.5]^2).
    auto onQuad = [&](int x, int y) {
        const glm::vec3 d = camera.direction((static_cast<float>(x) + 0.5f) / static_cast<float>(w),
                                             (static_cast<float>(y) + 0.5f) / static_cast<float>(h));
        return camera.origin + (-camera.origin.z / d.z) * d;
    };
    const float pixel = 2.0f * 3.0f * std::tan(glm::radians(30.0f)) / static_cast<float>(w);  // at z = 0
    const float edge = static_cast<float>(GEOMETRIC_EDGE_VALUE);
    int inside = 0, border = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const glm::vec3 q = onQuad(x, y);
            const float r = std::max(std::fabs(q.x), std::fabs(q.y));
            if (r < 0.5f - 3.0f * pixel) {  // through the hole: the planar wall, no edge
                ++inside;
                EXPECT_EQ(masked.edges.at(x, y), 0.0f) << "inside the hole at " << x << "," << y;
                EXPECT_EQ(maskedLit.edges.at(x, y), 0.0f) << "lit, inside the hole at " << x << "," << y;
            }
            if (std::fabs(r - 0.5f) < 0.5f * pixel) {  // the cut-out's outline
                ++border;
                float m = 0.0f, mLit = 0.0f;
                for (int j = std::max(y - 1, 0); j <= std::min(y + 1, h - 1); ++j)
                    for (int i = std::max(x - 1, 0); i <= std::min(x + 1, w - 1); ++i) {
                        m = std::max(m, masked.edges.at(i, j));
                        mLit = std::max(mLit, maskedLit.edges.at(i, j));
                    }
                EXPECT_EQ(m, edge) << "outline at " << x << "," << y;
                EXPECT_EQ(mLit, edge) << "lit, outline at " << x << "," << y;
            }
            if (r < 1.0f - 3.0f * pixel) {  // opaque: one planar quad, whatever its texels say
                EXPECT_EQ(opaque.edges.at(x, y), 0.0f) << "opaque quad at " << x << "," << y;
            }
        }
    EXPECT_GT(inside, 100);
    EXPECT_GT(border, 40);
}

}  // namespace
}  // namespace aamap::test
