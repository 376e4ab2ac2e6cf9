// Planar mirrors in the Snapshot: a mirror facing a coloured object shows the object exactly
// where the camera reflected in the mirror plane sees it, times the mirror's reflectance; the
// mirror passes exist only when a planar mirror is in view, and --explain says why.
#include <algorithm>
#include <cmath>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>

#include <fmt/format.h>
#include <glm/geometric.hpp>

#include "gpu_fixture.h"
#include "passes/mirror.h"
#include "tests/common/mirror_scenes.h"
#include "tests/common/test_scenes.h"
#include "passes/snapshot.h"
#include "scene/camera.h"

namespace aamap::test {
namespace {

View frontView() {
    View v;
    v.position = {0.1f, -0.2f, 4.0f};
    v.direction = {0, 0, -1};
    v.up = {0, 1, 0};
    v.horizontalFovDeg = v.verticalFovDeg = 60.0f;
    return v;
}

glm::vec3 onPlane(glm::vec3 origin, glm::vec3 d, float z) { return origin + ((z - origin.z) / d.z) * d; }

class SnapshotMirror : public GpuTest {};  // the suite names the feature a failure is in

TEST_F(SnapshotMirror, MirrorShowsTheObjectWhereTheReflectedCameraSeesIt) {
    const Scene scene = mirrorScene(MaterialKind::Mirror);
    const View view = frontView();
    SnapshotRenderer renderer(context(), scene);
    const SnapshotResult r = renderer.render(view, 64, 64, SnapshotSettings{});
    const PinholeCamera camera = PinholeCamera::fromView(view);
    const int w = r.snapshot.width(), h = r.snapshot.height();
    const float margin = 0.04f;
    int reflected = 0, empty = 0;
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            const glm::vec3 d = camera.direction((x + 0.5f) / w, (y + 0.5f) / h);
            const glm::vec3 direct = onPlane(camera.origin, d, 2.0f);
            if (!kObject.outside(direct, margin)) continue;  // the object's unlit back, or its edge
            const glm::vec3 m = onPlane(camera.origin, d, 0.0f);
            if (!kMirror.inside(m, margin)) continue;
            // The ray reflected at m (z flips) meets the object's plane at q.
            const glm::vec3 q = onPlane(m, {d.x, d.y, -d.z}, 2.0f);
            const glm::vec3 got = r.snapshot.at(x, y);
            if (kObject.inside(q, margin)) {
                for (int c = 0; c < 3; ++c)
                    ASSERT_NEAR(got[c], kReflectance[c] * kEmission[c], 1e-5f) << "pixel " << x << "," << y;
                ++reflected;
            } else if (kObject.outside(q, margin)) {
                ASSERT_EQ(got, glm::vec3(0.0f)) << "pixel " << x << "," << y;
                ++empty;
            }
        }
    }
    EXPECT_GT(reflected, 50);
    EXPECT_GT(empty, 500);

    // The object's centre, reflected to z = -2, projects to the pixel that shows it.
    const glm::vec3 centre(0.5f * (kObject.x0 + kObject.x1), 0.5f * (kObject.y0 + kObject.y1), -2.0f);
    const glm::vec3 toCentre = centre - camera.origin;
    const float along = glm::dot(toCentre, camera.forward);
    const float u = 0.5f + 0.5f * glm::dot(toCentre, camera.right) / (along * camera.tanHalfH);
    const float v = 0.5f - 0.5f * glm::dot(toCentre, camera.up) / (along * camera.tanHalfV);
    const glm::vec3 atCentre = r.snapshot.at(static_cast<int>(u * w), static_cast<int>(v * h));
    EXPECT_NEAR(atCentre.r, kReflectance.r * kEmission.r, 1e-5f);

    // The passes and why they run.
    std::set<std::string> names;
    for (const PassTiming& t : r.passTimes) names.insert(t.pass);
    EXPECT_TRUE(names.count("mirror") && names.count("mirror.mask") && names.count("mirror.composite"));
    EXPECT_NE(r.explain.find("1 planar mirror"), std::string::npos) << r.explain;
}

TEST_F(SnapshotMirror, MirrorPassesOnlyForAPlanarMirrorInView) {
    const auto passes = [&](const Scene& scene, const View& view, std::string* explain = nullptr) {
        SnapshotRenderer renderer(context(), scene);
        const SnapshotResult r = renderer.render(view, 32, 32, SnapshotSettings{});
        if (explain) *explain = r.explain;
        std::set<std::string> names;
        for (const PassTiming& t : r.passTimes) names.insert(t.pass);
        return names;
    };
    const std::set<std::string> withMirror = passes(mirrorScene(MaterialKind::Mirror), frontView());
    std::string why;
    const std::set<std::string> without = passes(mirrorScene(MaterialKind::Diffuse), frontView(), &why);
    std::set<std::string> added;
    std::set_difference(withMirror.begin(), withMirror.end(), without.begin(), without.end(),
                        std::inserter(added, added.end()));
    // The mirror's three passes, and the greyscale, which the G-buffer writes itself only when no
    // composite changes the snapshot after it.
    EXPECT_EQ(added, (std::set<std::string>{"mirror", "mirror.mask", "mirror.composite", "luminance"}));
    EXPECT_TRUE(std::includes(withMirror.begin(), withMirror.end(), without.begin(), without.end()));
    EXPECT_NE(why.find("no mirror"), std::string::npos) << why;

    // Looking away from the mirror: no mirror passes, and the reason says it is out of view.
    View away = frontView();
    away.direction = {0, 0, 1};
    EXPECT_EQ(passes(mirrorScene(MaterialKind::Mirror), away, &why), without);
    EXPECT_NE(why.find("in view"), std::string::npos) << why;
}

TEST_F(SnapshotMirror, MirrorUnderALightWithShadowsAndAlphaMaskedTextures) {
    // Every pipeline variant of the reflected view at once: shadowed and textured (the object
    // gets a texture whose left half is cut out), lit by a light between mirror and object.
    Scene scene = mirrorScene(MaterialKind::Mirror);
    Texture half;
    half.width = half.height = 4;
    half.rgba.assign(4 * 4 * 4, 1.0f);
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 2; ++x) half.rgba[4 * (y * 4 + x) + 3] = 0.0f;
    scene.textures.push_back(half);
    scene.materials[1].ke = glm::vec3(0.0f);
    scene.materials[1].kd = glm::vec3(0.8f);
    scene.materials[1].diffuseTexture = scene.materials[1].alphaTexture = 0;
    scene.materials[1].alphaMode = AlphaMode::Mask;
    scene.mesh.uvs = {{0, 1}, {1, 1}, {1, 0}, {0, 0}, {0, 1}, {1, 1}, {1, 0}, {0, 0}};
    addBulb(scene);
    SnapshotRenderer renderer(context(), scene);
    const SnapshotResult r = renderer.render(frontView(), 64, 64, SnapshotSettings{});
    std::set<std::string> names;
    for (const PassTiming& t : r.passTimes) names.insert(t.pass);
    EXPECT_TRUE(names.count("shadow") && names.count("mirror"));
    // Some mirror pixels show the lit object's right half (x > 0.9 on the object).
    const PinholeCamera camera = PinholeCamera::fromView(frontView());
    const int w = r.snapshot.width(), h = r.snapshot.height();
    int litRight = 0, cutLeft = 0;
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            const glm::vec3 d = camera.direction((x + 0.5f) / w, (y + 0.5f) / h);
            if (!kObject.outside(onPlane(camera.origin, d, 2.0f), 0.04f)) continue;
            const glm::vec3 m = onPlane(camera.origin, d, 0.0f);
            if (!kMirror.inside(m, 0.04f)) continue;
            const glm::vec3 q = onPlane(m, {d.x, d.y, -d.z}, 2.0f);
            if (!kObject.inside(q, 0.04f)) continue;
            const float split = 0.5f * (kObject.x0 + kObject.x1);
            if (q.x > split + 0.05f) litRight += r.snapshot.at(x, y).r > 0.0f;
            if (q.x < split - 0.05f) cutLeft += r.snapshot.at(x, y).r == 0.0f;
        }
    }
    EXPECT_GT(litRight, 10);
    EXPECT_GT(cutLeft, 10);
}

// The frame's bevel strips are planes of their own: the big plane reflects exactly what the same
// mirror without a frame reflects.
TEST_F(SnapshotMirror, AFramedMirrorReflectsLikeAPlainOne) {
    const View view = frontView();
    SnapshotRenderer plainRenderer(context(), mirrorScene(MaterialKind::Mirror));
    const SnapshotResult plain = plainRenderer.render(view, 64, 64, SnapshotSettings{});
    SnapshotRenderer framedRenderer(context(), framedMirrorScene());
    const SnapshotResult framed = framedRenderer.render(view, 64, 64, SnapshotSettings{});
    EXPECT_NE(framed.explain.find("'object 0/mirror plane 1'"), std::string::npos) << framed.explain;
    const PinholeCamera camera = PinholeCamera::fromView(view);
    const int w = plain.snapshot.width(), h = plain.snapshot.height();
    ASSERT_EQ(framed.snapshot.width(), w);
    int compared = 0, reflecting = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const glm::vec3 d = camera.direction((x + 0.5f) / w, (y + 0.5f) / h);
            if (!kObject.outside(onPlane(camera.origin, d, 2.0f), 0.04f)) continue;
            if (!kMirror.inside(onPlane(camera.origin, d, 0.0f), 0.04f)) continue;
            const glm::vec3 a = plain.snapshot.at(x, y), b = framed.snapshot.at(x, y);
            for (int c = 0; c < 3; ++c) ASSERT_NEAR(a[c], b[c], 1e-5f) << "pixel " << x << "," << y;
            ++compared;
            reflecting += a.r > 0.0f;
        }
    EXPECT_GT(compared, 500);
    EXPECT_GT(reflecting, 50);
}

// Each face of a mirrored cube is a plane that reflects: three emitters of three colours, each
// where one visible face's reflected rays go, show up in exactly that face's pixels.
TEST_F(SnapshotMirror, EachVisibleFaceOfAMirroredCubeReflects) {
    Scene scene = mirrorScene(MaterialKind::Mirror);
    scene.mesh = {};
    scene.materials.resize(1);
    addCube(scene, 0, 0);
    const glm::vec3 emission[3] = {{2, 0, 0}, {0, 2, 0}, {0, 0, 2}};  // the emitter in the plane axis = 6
    const float far = 6.0f, extent = 40.0f;
    for (int axis = 0; axis < 3; ++axis) {
        Material glow;
        glow.name = fmt::format("glow{}", axis);
        glow.kd = glm::vec3(0.0f);
        glow.ke = emission[axis];
        scene.materials.push_back(glow);
        const int u = (axis + 1) % 3, v = (axis + 2) % 3;
        glm::vec3 c[4];
        const float us[4] = {-extent, extent, extent, -extent}, vs[4] = {-extent, -extent, extent, extent};
        for (int k = 0; k < 4; ++k) {
            c[k][axis] = far;
            c[k][u] = us[k];
            c[k][v] = vs[k];
        }
        addPolygon(scene, {c[0], c[3], c[2], c[1]}, static_cast<std::uint32_t>(axis + 1),  // facing the cube
                   static_cast<std::uint32_t>(axis + 1));
    }
    View view;
    view.position = {3.2f, 2.6f, 3.0f};
    view.direction = glm::normalize(-view.position);
    view.up = {0, 1, 0};
    view.horizontalFovDeg = view.verticalFovDeg = 40.0f;
    SnapshotRenderer renderer(context(), scene);
    const SnapshotResult r = renderer.render(view, 64, 64, SnapshotSettings{});
    EXPECT_NE(r.explain.find("planar mirror(s) in view reflected"), std::string::npos) << r.explain;
    const PinholeCamera camera = PinholeCamera::fromView(view);
    const int w = r.snapshot.width(), h = r.snapshot.height();
    int pixels[3] = {0, 0, 0}, matching[3] = {0, 0, 0};
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const glm::vec3 d = camera.direction((x + 0.5f) / w, (y + 0.5f) / h);
            // The face the camera ray enters the cube through: the largest slab entry.
            float enter = -INFINITY, leave = INFINITY;
            int axis = -1;
            for (int k = 0; k < 3; ++k) {
                const float t0 = (-1.0f - camera.origin[k]) / d[k], t1 = (1.0f - camera.origin[k]) / d[k];
                if (std::min(t0, t1) > enter) {
                    enter = std::min(t0, t1);
                    axis = k;
                }
                leave = std::min(leave, std::max(t0, t1));
            }
            if (!(enter < leave) || enter <= 0.0f) continue;
            const glm::vec3 p = camera.origin + enter * d;
            if (std::fabs(p[(axis + 1) % 3]) > 0.9f || std::fabs(p[(axis + 2) % 3]) > 0.9f) continue;  // near an edge
            ASSERT_GT(p[axis], 0.0f);  // the camera sees the +x, +y and +z faces
            // The reflected ray, which goes to the emitter in the plane axis = 6.
            glm::vec3 reflected = d;
            reflected[axis] = -reflected[axis];
            const glm::vec3 q = p + ((far - p[axis]) / reflected[axis]) * reflected;
            if (std::fabs(q[(axis + 1) % 3]) > extent - 1.0f || std::fabs(q[(axis + 2) % 3]) > extent - 1.0f) continue;
            ++pixels[axis];
            const glm::vec3 got = r.snapshot.at(x, y), want = kReflectance * emission[axis];
            matching[axis] += glm::length(got - want) < 1e-4f;
        }
    for (int axis = 0; axis < 3; ++axis) {
        EXPECT_GT(pixels[axis], 40) << "face " << axis;
        EXPECT_EQ(matching[axis], pixels[axis]) << "face " << axis;
    }
}

// A tessellated sphere of mirror material is curved: no mirror pass, and --explain says why.
TEST_F(SnapshotMirror, ATessellatedMirrorSphereIsCurved) {
    Scene scene = mirrorScene(MaterialKind::Mirror);
    scene.mesh = {};
    addSphere(scene, {0, 0, 0}, 1.5f, 12, 6, 0, 0);
    addRect(scene, kObject, 2.0f, false, 1);
    SnapshotRenderer renderer(context(), scene);
    const SnapshotResult r = renderer.render(frontView(), 32, 32, SnapshotSettings{});
    std::set<std::string> passes;
    for (const PassTiming& t : r.passTimes) passes.insert(t.pass);
    EXPECT_FALSE(passes.contains("mirror") || passes.contains("mirror.mask") || passes.contains("mirror.composite"));
    EXPECT_TRUE(passes.contains("mirror.probes") && passes.contains("mirror.probes.composite"));
    EXPECT_NE(r.explain.find("mirrors: no mirror pass: 1 mirror group(s) are curved"), std::string::npos) << r.explain;
    EXPECT_NE(r.explain.find("curved mirrors: 1 curved mirror group(s) reflected"), std::string::npos) << r.explain;
    EXPECT_NE(r.explain.find("object 0/mirror: 120 triangles curved"), std::string::npos) << r.explain;
}

// The budget: a mirror too small in the image to hold a reflected edge is not reflected (its
// pixels keep the diffuse part, black here); four times as wide, the same mirror reflects.
TEST_F(SnapshotMirror, AMirrorUnderThePixelBudgetIsNotReflected) {
    // The point of z = 0 that shows the object's centre, seen from frontView().
    const glm::vec3 eye = frontView().position, mirrored(eye.x, eye.y, -eye.z);
    const glm::vec3 target(0.5f * (kObject.x0 + kObject.x1), 0.5f * (kObject.y0 + kObject.y1), 2.0f);
    const glm::vec3 centre = onPlane(mirrored, target - mirrored, 0.0f);
    const auto render = [&](float side, SnapshotResult& r) {
        Scene scene = mirrorScene(MaterialKind::Mirror);
        for (int k = 0; k < 4; ++k) {
            glm::vec3& p = scene.mesh.positions[k];
            p = centre + side / (kMirror.x1 - kMirror.x0) * glm::vec3(p.x, p.y, 0.0f);
        }
        SnapshotRenderer renderer(context(), scene);
        r = renderer.render(frontView(), 64, 64, SnapshotSettings{});
        // The mirror's coverage, as the budget estimates it.
        const PinholeCamera camera = PinholeCamera::fromView(frontView());
        const glm::mat4 viewProj = camera.projectionMatrix(0.01f, 100.0f) * camera.viewMatrix();
        const double covered = projectedPixels(
            scene.mesh.positions, scene.mesh.triangles, {0, 1}, viewProj, 0.01f,
            {static_cast<std::uint32_t>(r.snapshot.width()), static_cast<std::uint32_t>(r.snapshot.height())});
        // The snapshot pixel at the mirror's centre.
        const glm::vec3 toCentre = centre - camera.origin;
        const float along = glm::dot(toCentre, camera.forward);
        const float u = 0.5f + 0.5f * glm::dot(toCentre, camera.right) / (along * camera.tanHalfH);
        const float v = 0.5f - 0.5f * glm::dot(toCentre, camera.up) / (along * camera.tanHalfV);
        return std::pair{covered, r.snapshot.at(static_cast<int>(u * r.snapshot.width()),
                                                static_cast<int>(v * r.snapshot.height()))};
    };
    SnapshotResult small, large;
    const auto [smallPixels, smallCentre] = render(0.1f, small);
    const auto [largePixels, largeCentre] = render(0.4f, large);
    ASSERT_GT(smallPixels, 1.0);
    ASSERT_LT(smallPixels, passes::MirrorPass::kMinReflectedPixels);
    ASSERT_GT(largePixels, passes::MirrorPass::kMinReflectedPixels);
    for (const PassTiming& t : small.passTimes) EXPECT_NE(t.pass.rfind("mirror", 0), 0u) << t.pass;
    EXPECT_NE(small.explain.find("0 of the 1 planar mirror(s) in view reflected; 1 plane(s) skipped for the budget"),
              std::string::npos)
        << small.explain;
    EXPECT_EQ(smallCentre, glm::vec3(0.0f));
    EXPECT_NE(large.explain.find("1 planar mirror(s) in view reflected"), std::string::npos) << large.explain;
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(largeCentre[c], kReflectance[c] * kEmission[c], 1e-5f);
}

// What the Snapshot cannot show is named up front: a planar mirror is no limitation, a curved one
// and glass are, each in one sentence.
TEST(MirrorGeometry, LimitationsNameCurvedMirrorsAndGlass) {
    Scene s = mirrorScene(MaterialKind::Mirror);
    EXPECT_TRUE(snapshotLimitations(s).empty());
    addSphere(s, {0, 0, 1}, 0.5f, 12, 6, 0, 5);
    std::vector<std::string> notes = snapshotLimitations(s);
    ASSERT_EQ(notes.size(), 1u);
    EXPECT_NE(notes[0].find("not planar"), std::string::npos) << notes[0];
    EXPECT_NE(notes[0].find("object 5/mirror: 120 triangles curved"), std::string::npos) << notes[0];
    s = mirrorScene(MaterialKind::Glass);
    notes = snapshotLimitations(s);
    ASSERT_EQ(notes.size(), 1u);
    EXPECT_NE(notes[0].find("2 glass triangle(s)"), std::string::npos) << notes[0];
}

// passes/snapshot_graph.h names every pass and resource of the Snapshot graph, and nothing else:
// the nodes of the DOT graphs of a scene with every feature (a light, a planar mirror in view,
// each map source, block sums, debug images) are exactly the header's names.
TEST_F(SnapshotMirror, EveryPassAndResourceIsNamedInTheSnapshotGraphHeader) {
    std::ifstream in(std::string(AAMAP_SOURCE_DIR) + "/passes/snapshot_graph.h");
    ASSERT_TRUE(in.good());
    std::stringstream text;
    text << in.rdbuf();
    const std::string header = text.str();
    std::set<std::string> declared;
    const std::regex constant(R"re(inline const std::string k\w+ = "([^"]+)";)re");
    for (auto it = std::sregex_iterator(header.begin(), header.end(), constant); it != std::sregex_iterator(); ++it)
        declared.insert((*it)[1]);  // a pass may share its output's name (laplacian, mirror.mask)

    Scene scene = mirrorScene(MaterialKind::Mirror);
    addBulb(scene);
    SnapshotRenderer renderer(context(), scene);
    std::set<std::string> used;
    // A node's label starts with its name: "name\n<size>" for a resource, "i: name" for a kept
    // pass, "name (culled)" for a culled one.
    const std::regex node(R"re(\[shape=\w+[^\]]*label="(\d+: )?([^"\\ ]+))re");
    for (const passes::AamapSource source :
         {passes::AamapSource::Luminance, passes::AamapSource::Geometric, passes::AamapSource::Combined,
          passes::AamapSource::Subpixel}) {
        SnapshotSettings settings;
        settings.map = source;
        settings.blockSums = true;
        const SnapshotResult r = renderer.render(frontView(), 32, 32, settings);
        for (auto it = std::sregex_iterator(r.dot.begin(), r.dot.end(), node); it != std::sregex_iterator(); ++it) {
            const std::string name = (*it)[2];
            EXPECT_TRUE(declared.count(name)) << name << " is not in passes/snapshot_graph.h";
            used.insert(name);
        }
    }
    for (const std::string& name : declared) EXPECT_TRUE(used.count(name)) << name << " is declared but never used";
}

// A curved mirror reflects through its probe: a chrome sphere seen straight on shows, at its
// centre, the emitter behind the camera (reflected straight back), and at its right rim the
// emitter on its right (reflected sideways), each at reflectance x emission.
TEST_F(SnapshotMirror, ACurvedMirrorShowsWhatItsProbeSees) {
    Scene scene;
    scene.name = "chrome-sphere";
    Material chrome, red, green;
    chrome.kind = MaterialKind::Mirror;
    chrome.kd = glm::vec3(0.0f);
    chrome.ks = glm::vec3(0.8f);
    red.kd = glm::vec3(0.0f);
    red.ke = {5.0f, 0.0f, 0.0f};
    green.kd = glm::vec3(0.0f);
    green.ke = {0.0f, 3.0f, 0.0f};
    scene.materials = {chrome, red, green};
    addSphere(scene, {0, 0, 0}, 1.0f, 48, 24, 0, 0);
    // A quad of `material` through `centre` whose front (winding and normals) faces `normal`.
    const auto addFacing = [&](glm::vec3 centre, glm::vec3 normal, glm::vec3 u, std::uint32_t material) {
        const glm::vec3 v = glm::cross(normal, u);
        const auto base = static_cast<std::uint32_t>(scene.mesh.positions.size());
        for (const glm::vec2 c : {glm::vec2(-1, -1), glm::vec2(1, -1), glm::vec2(1, 1), glm::vec2(-1, 1)}) {
            scene.mesh.positions.push_back(centre + 20.0f * (c.x * u + c.y * v));
            scene.mesh.normals.push_back(normal);
        }
        scene.mesh.triangles.insert(scene.mesh.triangles.end(), {{base, base + 1, base + 2}, {base, base + 2, base + 3}});
        scene.mesh.materialIds.insert(scene.mesh.materialIds.end(), 2, material);
        scene.mesh.objectIds.insert(scene.mesh.objectIds.end(), 2, material);
    };
    addFacing({0, 0, 8}, {0, 0, -1}, {1, 0, 0}, 1);   // behind the camera, facing the sphere
    addFacing({8, 0, 0}, {-1, 0, 0}, {0, 0, 1}, 2);   // on the sphere's right
    const View view = viewDownZ({0.0f, 0.0f, 4.0f}, 40.0f);
    SnapshotRenderer renderer(context(), scene);
    constexpr int kSize = 64;
    const SnapshotResult r = renderer.render(view, kSize, kSize, SnapshotSettings{});
    ASSERT_NE(r.explain.find("curved mirrors: 1 curved mirror group(s) reflected"), std::string::npos) << r.explain;
    const glm::uvec2 snap{r.snapshot.width(), r.snapshot.height()};
    const glm::vec3 centre = r.snapshot.at(snap.x / 2, snap.y / 2);
    EXPECT_NEAR(centre.r, 0.8f * 5.0f, 0.01f);
    EXPECT_NEAR(centre.g, 0.0f, 1e-4f);
    // The right rim: the sphere's silhouette is at tan(asin(1 / 4)) of the half-field tan(20 deg).
    const float rim = std::tan(std::asin(0.25f)) / std::tan(glm::radians(20.0f)) * 0.5f * static_cast<float>(snap.x);
    const glm::vec3 right = r.snapshot.at(static_cast<int>(0.5f * snap.x + 0.93f * rim), snap.y / 2);
    EXPECT_NEAR(right.g, 0.8f * 3.0f, 0.01f) << "reflected sideways: the green emitter";
    EXPECT_NEAR(right.r, 0.0f, 1e-4f);
}

}  // namespace
}  // namespace aamap::test
