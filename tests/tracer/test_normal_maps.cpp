// Normal and bump maps (Mitsuba's normalmap / bumpmap): the tilted shading normal against its
// analytic value, and renders of a Lambert plane under a directional light in every shading mode.
#include <cmath>
#include <numbers>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>
#include <gtest/gtest.h>

#include "tests/tracer/material_scenes.h"
#include "tests/tracer/scene_builder.h"
#include "tracer/embree_scene.h"
#include "tracer/tracer.h"

namespace aamap {
namespace {

constexpr int kMapSize = 8;
constexpr float kMapRho = 0.5f;

// A texture of w x h texels, all `rgb` (exact floats, no 8-bit rounding).
Texture constantTexture(glm::vec3 rgb, int w = 2, int h = 2) {
    Texture t;
    t.path = "memory";
    t.width = w;
    t.height = h;
    for (int i = 0; i < w * h; ++i) t.rgba.insert(t.rgba.end(), {rgb.x, rgb.y, rgb.z, 1.0f});
    return t;
}

// The texel that encodes the unit tangent-space normal n: (n + 1) / 2.
glm::vec3 encode(glm::vec3 n) { return 0.5f * (n + 1.0f); }

// A plane y = 0 facing up, 100 x 100, u along +x and v along +z: dp/du = 100 x, dp/dv = 100 z, so
// Mitsuba's tangent frame is s = +x, t = n x s = -z. The material is a Lambert kMapRho, with
// `setup` applied to it (a map, a twosided flag).
template <class Setup>
Scene mapPlaneScene(Setup&& setup, std::vector<Texture> textures) {
    testing::SceneBuilder b;
    const auto mat = b.material("plane", glm::vec3(kMapRho));
    b.quad(glm::vec3(-50, 0, -50), glm::vec3(0, 0, 100), glm::vec3(100, 0, 0), mat);
    Scene s = std::move(b.scene());
    // Corners p0, p0 + a (+z), p0 + a + b, p0 + b (+x).
    s.mesh.uvs = {{0, 0}, {0, 1}, {1, 1}, {1, 0}};
    s.textures = std::move(textures);
    setup(s.materials[0]);
    return s;
}

Scene plainPlane() {
    return mapPlaneScene([](Material&) {}, {});
}

Scene normalMapped(glm::vec3 tangentNormal) {
    return mapPlaneScene([](Material& m) { m.normalMap = 0; }, {constantTexture(encode(tangentNormal))});
}

// A directional light arriving from unit direction `toLight`, irradiance E on a surface facing it.
void addSun(Scene& s, glm::vec3 toLight, float E) {
    DirectionalLight d;
    d.name = "sun";
    d.direction = -glm::normalize(toLight);
    d.irradiance = glm::vec3(E);
    s.directionalLights.push_back(d);
}

// An 8 x 8 view of the plane's middle from above (below: from under it, looking up).
ImageRGB renderMapped(const Scene& scene, ShadingMode mode, bool below = false) {
    View v;
    v.position = {0.0f, below ? -4.0f : 4.0f, 0.5f};
    v.direction = glm::normalize(glm::vec3(0.0f, below ? 1.0f : -1.0f, -0.1f));
    v.up = {0, 0, -1};
    v.horizontalFovDeg = v.verticalFovDeg = 30.0f;
    ShadingSettings shading;
    shading.mode = mode;
    shading.maxDepth = 3;
    return testing::renderScene(scene, v, shading, kMapSize, 1, 1, 5).image;
}

void expectEverywhere(const ImageRGB& img, float want, const char* what) {
    for (int y = 0; y < kMapSize; ++y)
        for (int x = 0; x < kMapSize; ++x)
            for (int ch = 0; ch < 3; ++ch)
                ASSERT_NEAR(img.at(x, y)[ch], want, 1e-3f * want) << what << " pixel " << x << "," << y;
}

const ShadingMode kModes[] = {ShadingMode::Direct, ShadingMode::Path, ShadingMode::Cache};

TEST(NormalMap, FlatMapRendersBitIdenticallyToNoMap) {
    for (ShadingMode mode : kModes) {
        Scene plain = plainPlane(), mapped = normalMapped({0, 0, 1});
        addSun(plain, glm::normalize(glm::vec3(0.3f, 1.0f, 0.2f)), 2.0f);
        addSun(mapped, glm::normalize(glm::vec3(0.3f, 1.0f, 0.2f)), 2.0f);
        const ImageRGB a = renderMapped(plain, mode), b = renderMapped(mapped, mode);
        for (int y = 0; y < kMapSize; ++y)
            for (int x = 0; x < kMapSize; ++x)
                for (int c = 0; c < 3; ++c)
                    ASSERT_EQ(a.at(x, y)[c], b.at(x, y)[c]) << toString(mode) << " pixel " << x << "," << y;
    }
}

// A constant map tilted by theta towards +s (+x) or +t (-z); the sun 40 degrees from the zenith
// on the same side: the Lambert plane shows rho / pi * E * cos(40 - theta) instead of cos(40).
TEST(NormalMap, ConstantTiltScalesRadianceByTheTiltedCosine) {
    const float theta = glm::radians(25.0f), phi = glm::radians(40.0f), E = 3.0f;
    struct Case {
        glm::vec3 tangent;  // the tilt in the map's frame
        glm::vec3 world;    // the same direction in the world: s = +x, t = -z
    };
    const Case cases[] = {{{1, 0, 0}, {1, 0, 0}}, {{0, 1, 0}, {0, 0, -1}}, {{-1, 0, 0}, {-1, 0, 0}}};
    for (ShadingMode mode : kModes) {
        for (const Case& c : cases) {
            Scene s = normalMapped(std::sin(theta) * c.tangent + std::cos(theta) * glm::vec3(0, 0, 1));
            addSun(s, std::sin(phi) * c.world + std::cos(phi) * glm::vec3(0, 1, 0), E);
            expectEverywhere(renderMapped(s, mode), kMapRho / std::numbers::pi_v<float> * E * std::cos(phi - theta),
                             toString(mode));
        }
    }
}

// Seen from below, twosided mirrors the directions it hands the map: the tilt keeps its tangent
// part (towards +x) and the normal turns down, so a sun below on the +x side shows cos(40 - 30).
// A map outside twosided tilts the frame first: the turned normal leans to -x, cos(40 + 30).
TEST(NormalMap, TwosidedMirrorsTheTiltOnTheBack) {
    const float theta = glm::radians(30.0f), phi = glm::radians(40.0f), E = 2.0f;
    const glm::vec3 tilt(std::sin(theta), 0.0f, std::cos(theta));
    for (bool mirrored : {true, false}) {
        Scene s = mapPlaneScene(
            [&](Material& m) {
                m.normalMap = 0;
                m.mapMirroredOnBack = mirrored;
            },
            {constantTexture(encode(tilt))});
        addSun(s, glm::vec3(std::sin(phi), -std::cos(phi), 0.0f), E);
        const float cosine = std::cos(mirrored ? phi - theta : phi + theta);
        expectEverywhere(renderMapped(s, ShadingMode::Direct, true), kMapRho / std::numbers::pi_v<float> * E * cosine,
                         mirrored ? "mirrored" : "turned");
    }
}

// A map may tilt the normal past the surface (Mitsuba does not turn it back). A camera above
// then sees it from below, and the hit reflects nothing, with a one-sided BSDF under the map or a
// twosided (Mitsuba's twosided there turns the normal to the viewer, but the map then passes only
// light from below the surface), although a sun on either side lights the plane.
TEST(NormalMap, ViewerBelowTheTiltedNormalSeesNoReflection) {
    const float theta = glm::radians(120.0f), E = 2.0f;  // past the view's 15 degrees off the vertical
    const glm::vec3 tilt(std::sin(theta), 0.0f, std::cos(theta));
    for (ShadingMode mode : kModes) {
        for (bool oneSided : {true, false}) {
            for (float side : {1.0f, -1.0f}) {
                Scene s = mapPlaneScene(
                    [&](Material& m) {
                        m.normalMap = 0;
                        m.oneSided = oneSided;
                        m.ke = glm::vec3(0.25f);  // emission stays
                    },
                    {constantTexture(encode(tilt))});
                addSun(s, glm::vec3(side * std::sin(glm::radians(60.0f)), std::cos(glm::radians(60.0f)), 0.0f), E);
                const ImageRGB img = renderMapped(s, mode);
                for (int y = 0; y < kMapSize; ++y)
                    for (int x = 0; x < kMapSize; ++x)
                        ASSERT_EQ(img.at(x, y), glm::vec3(0.25f)) << toString(mode) << " one-sided " << oneSided;
            }
        }
    }
}

TEST(NormalMap, DegenerateUvsKeepTheUnperturbedNormal) {
    Scene s = normalMapped(glm::normalize(glm::vec3(0.5f, 0.2f, 1.0f)));
    s.mesh.uvs.assign(4, glm::vec2(0.25f));  // every corner at one uv: no tangent frame
    const EmbreeScene es(s);
    const glm::vec3 n(0, 1, 0);
    const glm::vec3 got = es.perturbedNormal(es.material(0), 0, 0.2f, 0.3f, n);
    EXPECT_EQ(got, n);
}

TEST(BumpMap, ConstantHeightEqualsNoMap) {
    for (ShadingMode mode : kModes) {
        Scene plain = plainPlane();
        Scene bumped = mapPlaneScene(
            [](Material& m) {
                m.bumpMap = 0;
                m.bumpScale = 5.0f;
            },
            {constantTexture(glm::vec3(0.7f), 4, 4)});
        addSun(plain, glm::normalize(glm::vec3(-0.4f, 1.0f, 0.3f)), 1.5f);
        addSun(bumped, glm::normalize(glm::vec3(-0.4f, 1.0f, 0.3f)), 1.5f);
        const ImageRGB a = renderMapped(plain, mode), b = renderMapped(bumped, mode);
        for (int y = 0; y < kMapSize; ++y)
            for (int x = 0; x < kMapSize; ++x)
                for (int c = 0; c < 3; ++c)
                    ASSERT_EQ(a.at(x, y)[c], b.at(x, y)[c]) << toString(mode) << " pixel " << x << "," << y;
    }
}

// A height ramp along u (texels 0, 0.1, 0.2, 0.3 across a 4 x 1 texture) and along v: the
// normal of the height field h(u, v) = scale * height over the plane, n - grad h (in world
// units: dh/du / |dp/du| along s, dh/dv / |dp/dv| along dp/dv), normalised.
TEST(BumpMap, RampTiltsTheNormalAgainstTheHeightGradient) {
    Texture ramp;
    ramp.path = "ramp";
    ramp.width = 4;
    ramp.height = 1;
    for (int i = 0; i < 4; ++i) ramp.rgba.insert(ramp.rgba.end(), {0.1f * i, 0.1f * i, 0.1f * i, 1.0f});
    Texture rampV = ramp;
    rampV.width = 1;
    rampV.height = 4;
    const float scale = 20.0f;
    for (int axis = 0; axis < 2; ++axis) {
        Scene s = mapPlaneScene(
            [&](Material& m) {
                m.bumpMap = 0;
                m.bumpScale = scale;
            },
            {axis == 0 ? ramp : rampV});
        const EmbreeScene es(s);
        // Triangle 0 is (p0, p0 + a, p0 + a + b) with uvs (0, 0), (0, 1), (1, 1): at barycentrics
        // (bu, bv) its uv is (bv, bu + bv). Pick uv (0.4, 0.45): inside the ramps, away from the wrap.
        const float bv = 0.4f, bu = 0.05f;
        const glm::vec3 n = es.perturbedNormal(es.material(0), 0, bu, bv, glm::vec3(0, 1, 0));
        const float slope = scale * 0.1f * 4.0f / 100.0f;  // per texel, texels per uv, uv per world unit
        const glm::vec3 want = glm::normalize(axis == 0 ? glm::vec3(-slope, 1, 0) : glm::vec3(0, 1, -slope));
        EXPECT_NEAR(n.x, want.x, 1e-5f) << "axis " << axis;
        EXPECT_NEAR(n.y, want.y, 1e-5f) << "axis " << axis;
        EXPECT_NEAR(n.z, want.z, 1e-5f) << "axis " << axis;
    }
}

}  // namespace
}  // namespace aamap
