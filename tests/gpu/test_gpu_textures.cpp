// Textures and alpha masks in the Snapshot: masked texels cut holes in the G-buffer (and in the
// shadow cube maps), the aamap sees the cut-out boundary but nothing of the masked texels, the
// same model from OBJ and glTF rasterises the same, a minified texture shows its average over
// the pixel (mip chain and footprint filter), and the texture binding exists only for scenes
// that sample textures.
#include <algorithm>
#include <cmath>
#include <set>

#include <glm/geometric.hpp>

#include "tests/common/temp_dir.h"
#include "../scene/textured_quad_files.h"
#include "gpu_fixture.h"
#include "passes/gbuffer_textures.h"
#include "passes/snapshot.h"
#include "scene/camera.h"
#include "scene/gltf_loader.h"
#include "scene/obj_loader.h"
#include "core/texture_filter.h"
#include "tracer/embree_scene.h"

namespace aamap::test {
namespace {

constexpr float kPi = 3.14159265358979f;

// A square [-h, h]^2 in the plane z, facing +z, untextured (uvs 0 where the mesh has uvs).
void addBackWall(Scene& scene, float h, float z, float kd) {
    Material m;
    m.name = "wall";
    m.kd = glm::vec3(kd);
    const auto material = static_cast<std::uint32_t>(scene.materials.size());
    scene.materials.push_back(m);
    const auto base = static_cast<std::uint32_t>(scene.mesh.positions.size());
    scene.mesh.positions.insert(scene.mesh.positions.end(), {{-h, -h, z}, {h, -h, z}, {h, h, z}, {-h, h, z}});
    scene.mesh.normals.insert(scene.mesh.normals.end(), 4, glm::vec3(0, 0, 1));
    if (!scene.mesh.uvs.empty()) scene.mesh.uvs.insert(scene.mesh.uvs.end(), 4, glm::vec2(0.0f));
    scene.mesh.triangles.insert(scene.mesh.triangles.end(), {{base, base + 1, base + 2}, {base, base + 2, base + 3}});
    scene.mesh.materialIds.insert(scene.mesh.materialIds.end(), 2, material);
    scene.mesh.objectIds.insert(scene.mesh.objectIds.end(), 2, material);
}

void addLight(Scene& scene, glm::vec3 position, float intensity) {
    PointLight light;
    light.name = "bulb";
    light.position = position;
    light.intensity = glm::vec3(intensity);
    scene.pointLights.push_back(light);
}

View lookAt(glm::vec3 eye, glm::vec3 target, float fovDeg) {
    View v;
    v.position = eye;
    v.direction = glm::normalize(target - eye);
    v.up = {0, 1, 0};
    v.horizontalFovDeg = v.verticalFovDeg = fovDeg;
    return v;
}

// Where the camera ray through the centre of pixel (x, y) of a w x h image meets the plane z.
glm::vec3 hitPlane(const PinholeCamera& camera, int x, int y, int w, int h, float z) {
    const glm::vec3 d = camera.direction((static_cast<float>(x) + 0.5f) / static_cast<float>(w),
                                         (static_cast<float>(y) + 0.5f) / static_cast<float>(h));
    return camera.origin + ((z - camera.origin.z) / d.z) * d;
}

// The glTF quad (hole of half-width 0.5 in the middle, checker inside it) before a grey wall.
Scene maskedQuadScene(const TempDir& dir, const std::string& alphaMode, bool flat) {
    writePng(dir, "tex.png", 16, holeTexture(16, flat));
    Scene scene = loadGltf(writeQuadGltf(dir, "tex.png", alphaMode));
    addBackWall(scene, 6.0f, -1.0f, 0.5f);
    return scene;
}

class SnapshotTextures : public GpuTest {};  // the suite names the feature a failure is in

TEST_F(SnapshotTextures, AlphaMaskEdgesAtTheCutOutAndNoneInside) {
    TempDir dir;
    Scene scene = maskedQuadScene(dir, "MASK", true);
    addLight(scene, {0, 0, 3}, 30.0f);
    const View view = lookAt({0, 0, 3}, {0, 0, 0}, 60.0f);
    SnapshotSettings settings;
    settings.shadows.enabled = false;  // shadows have their own test below
    SnapshotRenderer renderer(context(), scene);
    const int w = 96, h = 96;
    const SnapshotResult r = renderer.render(view, w, h, settings);
    const PinholeCamera camera = PinholeCamera::fromView(view);

    // Snapshot: through the hole the wall, lit as Lambert predicts; the checker never shows.
    const int sw = r.snapshot.width(), sh = r.snapshot.height();
    const glm::vec3 wall = hitPlane(camera, sw / 2, sh / 2, sw, sh, -1.0f);
    const glm::vec3 toLight = scene.pointLights[0].position - wall;
    const float expected = 0.5f / kPi * 30.0f * (toLight.z / glm::length(toLight)) / glm::dot(toLight, toLight);
    EXPECT_NEAR(r.snapshot.at(sw / 2, sh / 2).r, expected, 1e-3f * expected);

    // aamap: zero for every pixel whose footprint lies well inside the hole; an edge wherever
    // a row crosses the hole's border (at x = +-0.5 on the quad).
    int inside = 0;
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            const glm::vec3 q = hitPlane(camera, x, y, w, h, 0.0f);
            const float pixel = 2.0f * 3.0f * std::tan(glm::radians(30.0f)) / static_cast<float>(w);  // at z = 0
            if (std::max(std::fabs(q.x), std::fabs(q.y)) < 0.5f - 4.0f * pixel) {
                EXPECT_EQ(r.aamap.at(x, y), 0.0f) << "inside the hole at " << x << "," << y;
                ++inside;
            }
        }
    }
    EXPECT_GT(inside, 100);
    for (int y = h / 2 - 5; y <= h / 2 + 5; ++y) {
        float left = 0.0f, right = 0.0f;
        for (int x = 0; x < w; ++x) {
            const float qx = hitPlane(camera, x, y, w, h, 0.0f).x;
            if (std::fabs(qx + 0.5f) < 0.05f) left = std::max(left, r.aamap.at(x, y));
            if (std::fabs(qx - 0.5f) < 0.05f) right = std::max(right, r.aamap.at(x, y));
        }
        EXPECT_GT(left, 0.1f) << "row " << y;
        EXPECT_GT(right, 0.1f) << "row " << y;
    }

    // Control: the same quad OPAQUE shows its checker in the hole, which the aamap flags.
    TempDir opaqueDir;
    Scene opaque = maskedQuadScene(opaqueDir, "OPAQUE", true);
    addLight(opaque, {0, 0, 3}, 30.0f);
    SnapshotRenderer opaqueRenderer(context(), opaque);
    const SnapshotResult o = opaqueRenderer.render(view, w, h, settings);
    EXPECT_GT(o.aamap.at(w / 2, h / 2), 0.5f);
}

TEST_F(SnapshotTextures, CutOutsCastCutOutShadows) {
    TempDir dir;
    Scene scene = maskedQuadScene(dir, "MASK", true);
    const glm::vec3 light(0, 0, 3);
    addLight(scene, light, 30.0f);
    // From the side, so that the quad's shadow on the wall is in view and not behind the quad.
    const View view = lookAt({5, 0, 3}, {0, 0, -1}, 50.0f);
    SnapshotSettings settings;
    settings.shadows.resolution = 512;
    SnapshotRenderer renderer(context(), scene);
    const SnapshotResult r = renderer.render(view, 64, 64, settings);
    const PinholeCamera camera = PinholeCamera::fromView(view);
    const int sw = r.snapshot.width(), sh = r.snapshot.height();
    int lit = 0, shadowed = 0;
    for (int y = 0; y < sh; ++y) {
        for (int x = 0; x < sw; ++x) {
            const glm::vec3 seen = hitPlane(camera, x, y, sw, sh, 0.0f);
            if (std::max(std::fabs(seen.x), std::fabs(seen.y)) < 1.05f) continue;  // the quad (or near it) is in front
            const glm::vec3 wall = hitPlane(camera, x, y, sw, sh, -1.0f);
            if (std::max(std::fabs(wall.x), std::fabs(wall.y)) > 5.5f) continue;
            // The segment from the wall point to the light crosses z = 0 a quarter of the way.
            const glm::vec3 q = wall + 0.25f * (light - wall);
            const float m = std::max(std::fabs(q.x), std::fabs(q.y));
            if (std::fabs(m - 1.0f) < 0.06f || std::fabs(m - 0.5f) < 0.06f) continue;  // near a shadow edge
            const bool blocked = m < 1.0f && m > 0.5f;
            const float value = r.snapshot.at(x, y).r;
            if (blocked) {
                EXPECT_EQ(value, 0.0f) << "pixel " << x << "," << y << " should be in the ring's shadow";
                ++shadowed;
            } else {
                EXPECT_GT(value, 0.0f) << "pixel " << x << "," << y << " should be lit (through the hole or beside)";
                ++lit;
            }
        }
    }
    EXPECT_GT(shadowed, 50);
    EXPECT_GT(lit, 50);
}

TEST_F(SnapshotTextures, ObjAndGltfGiveTheSameGBuffer) {
    TempDir dir;
    writePng(dir, "tex.png", 16, holeTexture(16, false));
    Scene fromObj = loadObj(writeQuadObj(dir, "tex.png"));
    Scene fromGltf = loadGltf(writeQuadGltf(dir, "tex.png"));
    for (Scene* s : {&fromObj, &fromGltf}) addLight(*s, {0.3f, 0.2f, 2.0f}, 5.0f);
    const View view = lookAt({0.2f, -0.1f, 3}, {0, 0, 0}, 50.0f);
    SnapshotSettings settings;
    SnapshotRenderer objRenderer(context(), fromObj);
    SnapshotRenderer gltfRenderer(context(), fromGltf);
    const SnapshotResult a = objRenderer.render(view, 48, 48, settings);
    const SnapshotResult b = gltfRenderer.render(view, 48, 48, settings);
    ASSERT_EQ(a.snapshot.width(), b.snapshot.width());
    int covered = 0, holes = 0;
    for (int y = 0; y < a.snapshot.height(); ++y) {
        for (int x = 0; x < a.snapshot.width(); ++x) {
            const glm::vec3 p = a.snapshot.at(x, y), q = b.snapshot.at(x, y);
            for (int c = 0; c < 3; ++c) ASSERT_NEAR(p[c], q[c], 1e-5f * std::max(1.0f, q[c])) << x << "," << y;
            covered += p.g > 0.0f;
        }
    }
    // The quad covers part of the image and its hole shows the black background.
    holes = a.snapshot.width() * a.snapshot.height() - covered;
    EXPECT_GT(covered, 500);
    EXPECT_GT(holes, 500);
    EXPECT_EQ(a.snapshot.at(a.snapshot.width() / 2, a.snapshot.height() / 2), glm::vec3(0.0f));
}

// Bilinear coverage (repeat, texel centres at (i + 0.5) / 16) of holeTexture(16) at uv.
float holeCoverage(glm::vec2 uv) {
    const auto alpha = [](int x, int y) {
        x = ((x % 16) + 16) % 16;
        y = ((y % 16) + 16) % 16;
        return x >= 4 && x < 12 && y >= 4 && y < 12 ? 0.0f : 1.0f;
    };
    const float x = uv.x * 16.0f - 0.5f, y = uv.y * 16.0f - 0.5f;
    const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
    const float ax = x - static_cast<float>(x0), ay = y - static_cast<float>(y0);
    const float top = (1.0f - ax) * alpha(x0, y0) + ax * alpha(x0 + 1, y0);
    const float bottom = (1.0f - ax) * alpha(x0, y0 + 1) + ax * alpha(x0 + 1, y0 + 1);
    return (1.0f - ay) * top + ay * bottom;
}

TEST_F(SnapshotTextures, SnapshotAndTracerCutTheSameTexels) {
    // The masked quad alone, at an angle: every snapshot pixel is lit iff the tracer's camera ray
    // through its centre hits (Embree with the alpha filter), except where the coverage at the
    // hit is within a hair of the cutoff or the ray grazes the quad's outline.
    TempDir dir;
    writePng(dir, "tex.png", 16, holeTexture(16, false));
    Scene scene = loadGltf(writeQuadGltf(dir, "tex.png", "MASK"));
    addLight(scene, {0.5f, 0.5f, 3.0f}, 20.0f);
    const View view = lookAt({1.2f, 0.7f, 2.5f}, {0.1f, 0.0f, 0.0f}, 55.0f);
    SnapshotSettings settings;
    SnapshotRenderer renderer(context(), scene);
    const SnapshotResult r = renderer.render(view, 64, 64, settings);
    const EmbreeScene tracer(scene);
    ASSERT_TRUE(tracer.features().alphaMask);
    const PinholeCamera camera = PinholeCamera::fromView(view);
    const int w = r.snapshot.width(), h = r.snapshot.height();
    int hits = 0, cut = 0;
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            const glm::vec3 d = camera.direction((x + 0.5f) / w, (y + 0.5f) / h);
            const glm::vec3 q = camera.origin + (-camera.origin.z / d.z) * d;  // the quad's plane, z = 0
            if (std::fabs(std::max(std::fabs(q.x), std::fabs(q.y)) - 1.0f) < 1e-3f) continue;
            const glm::vec2 uv(0.5f * (q.x + 1.0f), 0.5f * (1.0f - q.y));
            const bool onQuad = std::max(std::fabs(q.x), std::fabs(q.y)) < 1.0f;
            if (onQuad && std::fabs(holeCoverage(uv) - 0.5f) < 1e-3f) continue;
            RTCRayHit rh = makeRayHit(camera.origin, d);
            RTCIntersectContext context;
            rtcInitIntersectContext(&context);
            rtcIntersect1(tracer.handle(), &context, &rh);
            const bool traced = rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
            const bool rastered = r.snapshot.at(x, y).g > 0.0f;
            ASSERT_EQ(traced, rastered) << "pixel " << x << "," << y << " uv " << uv.x << "," << uv.y;
            hits += traced;
            cut += onQuad && !traced;
        }
    }
    EXPECT_GT(hits, 500);
    EXPECT_GT(cut, 200);
}

// The floor y = 0 over x in [-halfWidth, halfWidth], z in [far, near], kd 1 times `texture` at
// uv = uvPerUnit (x, z), lit from straight above with irradiance pi: its radiance is the
// texture's value. No shadows needed.
Scene floorScene(Texture texture, float halfWidth, float near, float far, float uvPerUnit) {
    Scene scene;
    scene.textures.push_back(std::move(texture));
    Material m;
    m.name = "floor";
    m.kd = glm::vec3(1.0f);
    m.diffuseTexture = 0;
    scene.materials.push_back(m);
    scene.mesh.positions = {{-halfWidth, 0, near}, {halfWidth, 0, near}, {halfWidth, 0, far}, {-halfWidth, 0, far}};
    scene.mesh.normals.assign(4, glm::vec3(0, 1, 0));
    for (const glm::vec3& p : scene.mesh.positions) scene.mesh.uvs.push_back(uvPerUnit * glm::vec2(p.x, p.z));
    scene.mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
    scene.mesh.materialIds = {0, 0};
    scene.mesh.objectIds = {0, 0};
    DirectionalLight sun;
    sun.name = "sun";
    sun.direction = {0, -1, 0};
    sun.irradiance = glm::vec3(kPi);
    scene.directionalLights.push_back(sun);
    return scene;
}

// side x side texels of a one-texel black/white checker (linear 0 and 1): mean 0.5.
Texture checkerTexture(int side) {
    Texture checker;
    checker.width = checker.height = side;
    checker.rgba.assign(static_cast<std::size_t>(side) * side * 4, 1.0f);
    for (int y = 0; y < side; ++y)
        for (int x = 0; x < side; ++x)
            for (int c = 0; c < 3; ++c)
                checker.rgba[4 * (static_cast<std::size_t>(y) * side + x) + c] = (x + y) % 2 ? 1.0f : 0.0f;
    return checker;
}

// A floor seen at a grazing angle, textured with a one-texel black/white checker of 1024^2 texels
// per world unit (many texels per pixel everywhere), lit evenly from straight above so that the
// snapshot is the texture's value times one. Filtered, every pixel well inside the floor is the
// checker's mean and the aamap sees nothing; a level-0 lookup at the pixel centre would be
// anywhere in [0, 1] (the test checks that it would fail its tolerance).
TEST_F(SnapshotTextures, MinifiedCheckerIsItsMeanAndUnflagged) {
    constexpr int kSide = 1024;
    constexpr float kHalfWidth = 40.0f, kNear = 2.0f, kFar = -80.0f;
    const Scene scene = floorScene(checkerTexture(kSide), kHalfWidth, kNear, kFar, 1.0f);  // 1 repeat per unit

    const View view = lookAt({0, 1, 0}, {0, 0, -8}, 60.0f);
    SnapshotSettings settings;
    settings.shadows.enabled = false;
    SnapshotRenderer renderer(context(), scene);
    const int w = 64, h = 64;
    const SnapshotResult r = renderer.render(view, w, h, settings);
    const PinholeCamera camera = PinholeCamera::fromView(view);

    // Pixel (x, y) of a width x height image and its neighbours `margin` pixels away all see the
    // floor's interior (not its far edge, the sky or its sides).
    const auto interior = [&](int x, int y, int width, int height, int margin) {
        for (int dy = -margin; dy <= margin; dy += margin)
            for (int dx = -margin; dx <= margin; dx += margin) {
                const glm::vec3 d = camera.direction((static_cast<float>(x + dx) + 0.5f) / static_cast<float>(width),
                                                     (static_cast<float>(y + dy) + 0.5f) / static_cast<float>(height));
                if (d.y >= 0.0f) return false;
                const glm::vec3 q = camera.origin + (-camera.origin.y / d.y) * d;
                if (std::fabs(q.x) > kHalfWidth - 2.0f || q.z < kFar + 2.0f) return false;
            }
        return true;
    };

    // The checker's mean, 0.5, within 5%: the 8-bit sRGB atlas holds 0.5 as 188 / 255 (0.503).
    constexpr float kMean = 0.5f, kTolerance = 0.05f * kMean;
    const int sw = r.snapshot.width(), sh = r.snapshot.height();
    int inside = 0, unfilteredOff = 0;
    for (int y = 0; y < sh; ++y) {
        for (int x = 0; x < sw; ++x) {
            if (!interior(x, y, sw, sh, 2)) continue;
            ++inside;
            const glm::vec3 c = r.snapshot.at(x, y);
            for (int k = 0; k < 3; ++k) EXPECT_NEAR(c[k], kMean, kTolerance) << "snapshot pixel " << x << "," << y;
            // The unfiltered lookup there: level 0 at the pixel centre's uv.
            const glm::vec3 d = camera.direction((static_cast<float>(x) + 0.5f) / static_cast<float>(sw),
                                                 (static_cast<float>(y) + 0.5f) / static_cast<float>(sh));
            const glm::vec3 q = camera.origin + (-camera.origin.y / d.y) * d;
            const float tx = q.x * kSide - 0.5f, ty = q.z * kSide - 0.5f;
            const float ax = tx - std::floor(tx), ay = ty - std::floor(ty);
            const float deviation = 0.5f * std::fabs((1.0f - 2.0f * ax) * (1.0f - 2.0f * ay));  // of a 1-texel checker
            unfilteredOff += deviation > kTolerance;
        }
    }
    EXPECT_GT(inside, sw * sh / 4);
    EXPECT_GT(unfilteredOff, inside / 2);  // the tolerance is one a level-0 lookup fails

    // The aamap inside the floor: the texture is not flagged.
    int mapInside = 0;
    float mapMax = 0.0f;
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            if (!interior(x, y, w, h, 4)) continue;
            ++mapInside;
            mapMax = std::max(mapMax, r.aamap.at(x, y));
        }
    }
    EXPECT_GT(mapInside, w * h / 5);
    EXPECT_LT(mapMax, 0.05f);
}

// The reflected view's shaders filter the same way: a mirror standing on the checker floor
// shows the floor's mean times its reflectance wherever the reflected ray meets the floor's
// interior.
TEST_F(SnapshotTextures, MirrorShowsTheFilteredFloor) {
    constexpr float kHalfWidth = 40.0f, kNear = 20.0f, kFar = -80.0f, kMirrorZ = -6.0f;
    constexpr float kReflectance = 0.5f;
    Scene scene = floorScene(checkerTexture(1024), kHalfWidth, kNear, kFar, 1.0f);
    Material mirror;
    mirror.name = "mirror";
    mirror.kind = MaterialKind::Mirror;
    mirror.kd = glm::vec3(0.0f);
    mirror.ks = glm::vec3(kReflectance);
    scene.materials.push_back(mirror);
    // x in [-3, 3], y in [0.05, 3] at z = kMirrorZ, facing the camera (+z).
    scene.mesh.positions.insert(scene.mesh.positions.end(),
                                {{-3, 0.05f, kMirrorZ}, {3, 0.05f, kMirrorZ}, {3, 3, kMirrorZ}, {-3, 3, kMirrorZ}});
    scene.mesh.normals.insert(scene.mesh.normals.end(), 4, glm::vec3(0, 0, 1));
    scene.mesh.uvs.insert(scene.mesh.uvs.end(), 4, glm::vec2(0.0f));
    scene.mesh.triangles.insert(scene.mesh.triangles.end(), {{4, 5, 6}, {4, 6, 7}});
    scene.mesh.materialIds.insert(scene.mesh.materialIds.end(), 2, 1u);
    scene.mesh.objectIds.insert(scene.mesh.objectIds.end(), 2, 1u);

    const View view = lookAt({0, 2, 0}, {0, 0.8f, -6}, 60.0f);
    SnapshotSettings settings;
    settings.shadows.enabled = false;
    SnapshotRenderer renderer(context(), scene);
    const SnapshotResult r = renderer.render(view, 64, 64, settings);
    const PinholeCamera camera = PinholeCamera::fromView(view);
    const int sw = r.snapshot.width(), sh = r.snapshot.height();
    // Pixel (x, y) sees the mirror and, reflected, the floor's interior.
    const auto reflectsFloor = [&](int x, int y) {
        const glm::vec3 d = camera.direction((static_cast<float>(x) + 0.5f) / static_cast<float>(sw),
                                             (static_cast<float>(y) + 0.5f) / static_cast<float>(sh));
        if (d.z >= 0.0f) return false;
        const glm::vec3 m = camera.origin + ((kMirrorZ - camera.origin.z) / d.z) * d;
        if (std::fabs(m.x) > 2.9f || m.y < 0.15f || m.y > 2.9f) return false;
        if (d.y >= 0.0f) return false;
        const glm::vec3 q = m + (-m.y / d.y) * glm::vec3(d.x, d.y, -d.z);  // reflected: z flips
        return std::fabs(q.x) < kHalfWidth - 2.0f && q.z < kNear - 0.5f;
    };
    int seen = 0;
    for (int y = 2; y < sh - 2; ++y) {
        for (int x = 2; x < sw - 2; ++x) {
            if (!reflectsFloor(x, y) || !reflectsFloor(x - 2, y - 2) || !reflectsFloor(x + 2, y + 2) ||
                !reflectsFloor(x - 2, y + 2) || !reflectsFloor(x + 2, y - 2))
                continue;
            const glm::vec3 c = r.snapshot.at(x, y);
            for (int k = 0; k < 3; ++k)
                EXPECT_NEAR(c[k], kReflectance * 0.5f, 0.05f * kReflectance * 0.5f) << "mirror pixel " << x << "," << y;
            ++seen;
        }
    }
    EXPECT_GT(seen, 300);
}

// The same floor with a random texture: each snapshot pixel is filteredLookup's colour for the
// footprint of the pixel's quad (the CPU rule of the tracer), at every probe count and level the
// view spans. Pixels where the derivatives of the quad's other row or column would give another
// probe count or base level are left out (the raster may take either).
TEST_F(SnapshotTextures, FilteredColourIsTheTracersRule) {
    constexpr int kSide = 256;
    constexpr float kHalfWidth = 20.0f, kNear = 2.0f, kFar = -40.0f, kRepeat = 0.25f;  // uv per world unit
    const auto decode = [](std::uint32_t byte) {
        const float c = static_cast<float>(byte) / 255.0f;
        return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
    };
    Texture noise;  // 8-bit sRGB values, so that level 0 is what the atlas stores
    noise.width = noise.height = kSide;
    noise.rgba.assign(static_cast<std::size_t>(kSide) * kSide * 4, 1.0f);
    std::uint32_t seed = 12345u;
    std::vector<glm::vec3> rgb(static_cast<std::size_t>(kSide) * kSide);
    for (std::size_t i = 0; i < rgb.size(); ++i) {
        for (int c = 0; c < 3; ++c) {
            seed = seed * 1664525u + 1013904223u;
            rgb[i][c] = noise.rgba[4 * i + static_cast<std::size_t>(c)] = decode(seed >> 24);
        }
    }
    const std::vector<MipLevel> chain = buildMipChain(kSide, kSide, rgb);
    const std::vector<PackedLevel> packed = packMipChain(chain);  // the tracer's texels
    ASSERT_EQ(packed[0].encoding(), TexelEncoding::Srgb8);
    const Scene scene = floorScene(noise, kHalfWidth, kNear, kFar, kRepeat);

    const View view = lookAt({0, 1, 0}, {0, 0, -6}, 60.0f);
    SnapshotSettings settings;
    settings.shadows.enabled = false;
    SnapshotRenderer renderer(context(), scene);
    const SnapshotResult r = renderer.render(view, 64, 64, settings);
    const PinholeCamera camera = PinholeCamera::fromView(view);
    const int sw = r.snapshot.width(), sh = r.snapshot.height();
    const auto floorAt = [&](int x, int y, glm::vec2& uv) {
        const glm::vec3 d = camera.direction((static_cast<float>(x) + 0.5f) / static_cast<float>(sw),
                                             (static_cast<float>(y) + 0.5f) / static_cast<float>(sh));
        if (d.y >= 0.0f) return false;
        const glm::vec3 q = camera.origin + (-camera.origin.y / d.y) * d;
        uv = kRepeat * glm::vec2(q.x, q.z);
        return std::fabs(q.x) < kHalfWidth - 1.0f && q.z > kFar + 1.0f;
    };
    const glm::vec2 size(static_cast<float>(kSide));
    const int levels = static_cast<int>(chain.size());
    int compared = 0, maxCount = 0;
    float maxLevel = 0.0f;
    for (int y = 0; y < sh - 1; ++y) {
        for (int x = 0; x < sw - 1; ++x) {
            const int x0 = x & ~1, y0 = y & ~1;  // the pixel's 2x2 quad
            glm::vec2 uv, q[2][2];
            bool inside = floorAt(x, y, uv);
            for (int j = 0; j < 2; ++j)
                for (int i = 0; i < 2; ++i) inside = floorAt(x0 + i, y0 + j, q[j][i]) && inside;
            if (!inside) continue;
            const FootprintProbes p = footprintProbes((q[y - y0][1] - q[y - y0][0]) * size, (q[1][x - x0] - q[0][x - x0]) * size, levels);
            bool stable = true;
            for (int j = 0; j < 2; ++j) {
                for (int i = 0; i < 2; ++i) {
                    const FootprintProbes o = footprintProbes((q[j][1] - q[j][0]) * size, (q[1][i] - q[0][i]) * size, levels);
                    stable = stable && o.count == p.count && std::floor(o.level) == std::floor(p.level);
                }
            }
            if (!stable) continue;
            const glm::vec3 expected = filteredLookup(packed, uv, q[y - y0][1] - q[y - y0][0], q[1][x - x0] - q[0][x - x0]);
            const glm::vec3 c = r.snapshot.at(x, y);
            // 8-bit sRGB levels: within 0.006 (0.5 / 255 in sRGB near white).
            for (int k = 0; k < 3; ++k)
                ASSERT_NEAR(c[k], expected[k], 0.006f) << "pixel " << x << "," << y << " probes " << p.count << " level " << p.level;
            ++compared;
            maxCount = std::max(maxCount, p.count);
            maxLevel = std::max(maxLevel, p.level);
        }
    }
    EXPECT_GT(compared, sw * sh / 4);
    EXPECT_EQ(maxCount, kMaxTextureAnisotropy);  // the view spans anisotropic footprints,
    EXPECT_GT(maxLevel, 4.0f);                   // and coarse levels
}

TEST(TextureAtlas, EntriesFitWithoutOverlapAndKeepTheirTexels) {
    Scene scene;
    const auto texture = [](int w, int h) {
        Texture t;
        t.width = w;
        t.height = h;
        t.rgba.resize(static_cast<std::size_t>(w) * h * 4);
        for (std::size_t i = 0; i < t.rgba.size(); ++i) t.rgba[i] = static_cast<float>((i * 37) % 256) / 255.0f;
        return t;
    };
    // The last one is narrow: its levels' row is wider than level 0 (they stop halving at width 1).
    scene.textures = {texture(5000, 40), texture(100, 100), texture(64, 32), texture(4, 300)};
    for (int i = 0; i < 4; ++i) {
        Material m;
        m.diffuseTexture = i;
        scene.materials.push_back(m);
        const auto base = static_cast<std::uint32_t>(scene.mesh.positions.size());
        scene.mesh.positions.insert(scene.mesh.positions.end(), {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
        scene.mesh.uvs.insert(scene.mesh.uvs.end(), {{0, 0}, {1, 0}, {0, 1}});
        scene.mesh.triangles.push_back({base, base + 1, base + 2});
        scene.mesh.materialIds.push_back(static_cast<std::uint32_t>(i));
    }
    const passes::TextureAtlas atlas = passes::buildTextureAtlas(scene);
    ASSERT_EQ(atlas.entries.size(), 4u);
    EXPECT_GE(atlas.layers, 2u);
    EXPECT_EQ(atlas.texels.size(), static_cast<std::size_t>(atlas.pageSide) * atlas.pageSide * atlas.layers);
    std::vector<passes::AtlasEntry> entries;
    for (const auto& [key, e] : atlas.entries) {
        EXPECT_LE(e.x + e.width, atlas.pageSide);
        EXPECT_LE(e.y + e.height, atlas.pageSide);
        EXPECT_LT(e.layer, atlas.layers);
        EXPECT_LE(std::max(e.width, e.height), passes::TextureAtlas::kMaxEntrySide);
        for (const passes::AtlasEntry& o : entries) {
            const bool apart = o.layer != e.layer || o.x + o.width <= e.x || e.x + e.width <= o.x ||
                               o.y + o.height <= e.y || e.y + e.height <= o.y;
            EXPECT_TRUE(apart);
        }
        entries.push_back(e);
    }
    EXPECT_EQ(atlas.entries.at({0, 0}).width, 1250u);  // 5000 halved twice
    EXPECT_EQ(atlas.entries.at({0, 0}).height, 10u);
    // An entry at its texture's size holds its texels (sRGB-encoded colour, linear alpha).
    const passes::AtlasEntry& e = atlas.entries.at({1, 1});
    const Texture& t = scene.textures[1];
    for (int y = 0; y < 100; y += 7) {
        for (int x = 0; x < 100; x += 11) {
            const std::uint32_t texel = atlas.texels[static_cast<std::size_t>(e.layer) * atlas.pageSide * atlas.pageSide +
                                                     static_cast<std::size_t>(e.y + y) * atlas.pageSide + e.x + x];
            const float* src = &t.rgba[4 * (static_cast<std::size_t>(y) * 100 + x)];
            const float linear = (texel & 0xffu) / 255.0f;
            const float encoded = src[0] <= 0.0031308f ? 12.92f * src[0] : 1.055f * std::pow(src[0], 1.0f / 2.4f) - 0.055f;
            EXPECT_NEAR(linear, encoded, 0.5f / 255.0f + 1e-5f);
            EXPECT_NEAR((texel >> 24) / 255.0f, src[3], 0.5f / 255.0f + 1e-5f);
        }
    }

    // Every level of every entry's chain lies in the page, apart from every other level, and holds
    // buildMipChain's texels (sRGB-encoded).
    std::vector<passes::AtlasEntry> levels;
    for (const auto& [key, entry] : atlas.entries) {
        const std::uint32_t count = passes::atlasLevelCount(entry.width, entry.height);
        const passes::AtlasEntry last = passes::atlasLevel(entry, count - 1);
        EXPECT_EQ(last.width, 1u);
        EXPECT_EQ(last.height, 1u);
        for (std::uint32_t l = 0; l < count; ++l) {
            const passes::AtlasEntry r = passes::atlasLevel(entry, l);
            EXPECT_LE(r.x + r.width, atlas.pageSide);
            EXPECT_LE(r.y + r.height, atlas.pageSide);
            for (const passes::AtlasEntry& o : levels) {
                const bool apart = o.layer != r.layer || o.x + o.width <= r.x || r.x + r.width <= o.x ||
                                   o.y + o.height <= r.y || r.y + r.height <= o.y;
                EXPECT_TRUE(apart) << "level " << l << " of the entry at " << entry.x << "," << entry.y;
            }
            levels.push_back(r);
        }
    }
    EXPECT_EQ(passes::atlasLevelCount(100, 100), 7u);  // 100 50 25 12 6 3 1
    EXPECT_EQ(passes::atlasLevelCount(1250, 10), 11u);
    const auto encode = [](float c) { return c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f; };
    for (int index : {1, 2, 3}) {
        const Texture& src = scene.textures[static_cast<std::size_t>(index)];
        std::vector<glm::vec3> rgb(static_cast<std::size_t>(src.width) * src.height);
        for (std::size_t i = 0; i < rgb.size(); ++i) rgb[i] = {src.rgba[4 * i], src.rgba[4 * i + 1], src.rgba[4 * i + 2]};
        const std::vector<MipLevel> chain = buildMipChain(src.width, src.height, rgb);
        const passes::AtlasEntry& entry = atlas.entries.at({index, index});
        ASSERT_EQ(chain.size(), passes::atlasLevelCount(entry.width, entry.height));
        for (std::uint32_t l = 0; l < chain.size(); ++l) {
            const passes::AtlasEntry r = passes::atlasLevel(entry, l);
            ASSERT_EQ(static_cast<int>(r.width), chain[l].width);
            ASSERT_EQ(static_cast<int>(r.height), chain[l].height);
            for (std::uint32_t y = 0; y < r.height; ++y) {
                for (std::uint32_t x = 0; x < r.width; ++x) {
                    const std::uint32_t texel = atlas.texels[static_cast<std::size_t>(r.layer) * atlas.pageSide * atlas.pageSide +
                                                             static_cast<std::size_t>(r.y + y) * atlas.pageSide + r.x + x];
                    const glm::vec3 expected = chain[l].rgb[static_cast<std::size_t>(y) * r.width + x];
                    for (int c = 0; c < 3; ++c)
                        ASSERT_NEAR(((texel >> (8 * c)) & 0xffu) / 255.0f, encode(expected[c]), 0.5f / 255.0f + 1e-4f)
                            << "texture " << index << " level " << l << " texel " << x << "," << y;
                }
            }
        }
    }
}

std::set<std::string> passNames(const SnapshotResult& r) {
    std::set<std::string> names;
    for (const PassTiming& t : r.passTimes) names.insert(t.pass);
    return names;
}

std::set<std::string> minus(const std::set<std::string>& a, const std::set<std::string>& b) {
    std::set<std::string> out;
    std::set_difference(a.begin(), a.end(), b.begin(), b.end(), std::inserter(out, out.end()));
    return out;
}

TEST_F(SnapshotTextures, SceneFeaturesAddExactlyTheirPassesAndBindings) {
    TempDir dir;
    writePng(dir, "tex.png", 16, holeTexture(16, true));
    const Scene textured = loadGltf(writeQuadGltf(dir, "tex.png", "MASK"));
    Scene plain = textured;  // the same geometry, untextured and opaque
    plain.materials[0].diffuseTexture = plain.materials[0].alphaTexture = -1;
    plain.materials[0].alphaMode = AlphaMode::Opaque;
    plain.textures.clear();
    Scene litPlain = plain, litTextured = textured;
    addLight(litPlain, {0, 0, 3}, 10.0f);
    addLight(litTextured, {0, 0, 3}, 10.0f);

    const View view = lookAt({0, 0, 3}, {0, 0, 0}, 60.0f);
    SnapshotSettings settings;
    const auto run = [&](const Scene& s) { return SnapshotRenderer(context(), s).render(view, 32, 32, settings); };
    const SnapshotResult rPlain = run(plain), rLit = run(litPlain), rTex = run(textured), rBoth = run(litTextured);

    // Lights add the shadow pass and nothing else; textures add no pass, only the atlas binding
    // (named in the G-buffer's purpose), and with masks the alpha test in the shadow pass.
    EXPECT_EQ(minus(passNames(rLit), passNames(rPlain)), std::set<std::string>{"shadow"});
    EXPECT_TRUE(minus(passNames(rPlain), passNames(rLit)).empty());
    EXPECT_EQ(passNames(rTex), passNames(rPlain));
    EXPECT_EQ(passNames(rBoth), passNames(rLit));
    EXPECT_EQ(rPlain.explain.find("atlas"), std::string::npos);
    EXPECT_EQ(rLit.explain.find("atlas"), std::string::npos);
    EXPECT_NE(rTex.explain.find("atlas"), std::string::npos);
    EXPECT_NE(rBoth.explain.find("alpha test from the texture atlas"), std::string::npos);
    EXPECT_EQ(rLit.explain.find("alpha test"), std::string::npos);

    // Textured but opaque: the atlas, and no alpha test anywhere.
    Scene litOpaque = litTextured;
    litOpaque.materials[0].alphaMode = AlphaMode::Opaque;
    const SnapshotResult rOpaque = run(litOpaque);
    EXPECT_EQ(passNames(rOpaque), passNames(rLit));
    EXPECT_NE(rOpaque.explain.find("atlas"), std::string::npos);
    EXPECT_EQ(rOpaque.explain.find("alpha test"), std::string::npos);
}

}  // namespace
}  // namespace aamap::test
