// Textures are antialiased by filtering, not by rays (docs/tracer.md, "Texture filtering"): a
// camera ray's cone covers its share of the pixel, and the albedo is the texture filtered over the
// cone's footprint. So one ray per pixel on a minified texture already shows what many rays
// average, while a magnified texture is looked up exactly as without filtering.
#include <cmath>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "core/texture_filter.h"
#include "tracer/tracer.h"

namespace aamap {
namespace {

// A side x side checkerboard of single-texel black and white checks (linear 0.05 and 0.95).
Texture checkerboard(int side) {
    Texture t;
    t.width = t.height = side;
    t.rgba.resize(static_cast<std::size_t>(side) * side * 4);
    for (int y = 0; y < side; ++y)
        for (int x = 0; x < side; ++x) {
            const float c = (x + y) % 2 == 0 ? 0.95f : 0.05f;
            float* p = &t.rgba[4 * (static_cast<std::size_t>(y) * side + x)];
            p[0] = p[1] = p[2] = c;
            p[3] = 1.0f;
        }
    return t;
}

// A floor y = 0 over x in [-half, half], z in [-depth, 0], with `repeats` copies of the texture
// along each side, under a directional light straight down (irradiance pi: radiance = albedo).
Scene texturedFloor(int side, float repeats, float half, float depth) {
    Scene s;
    s.name = "textured floor";
    s.textures.push_back(checkerboard(side));
    Material m;
    m.name = "floor";
    m.kd = glm::vec3(1.0f);
    m.diffuseTexture = 0;
    s.materials.push_back(m);
    TriangleMesh& mesh = s.mesh;
    mesh.positions = {{-half, 0, 0}, {half, 0, 0}, {half, 0, -depth}, {-half, 0, -depth}};
    mesh.normals.assign(4, glm::vec3(0, 1, 0));
    mesh.uvs = {{0, 0}, {repeats, 0}, {repeats, repeats}, {0, repeats}};
    mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
    mesh.materialIds = {0, 0};
    mesh.objectIds = {0, 0};
    DirectionalLight sun;
    sun.name = "sun";
    sun.direction = {0, -1, 0};
    sun.irradiance = glm::vec3(static_cast<float>(M_PI));
    s.directionalLights.push_back(sun);
    return s;
}

// Looks along the floor from height 1, tilted down: the floor fills the lower part of the image
// up to its far edge; every pixel below `firstFloorRow` sees the floor across its whole width.
View floorView() {
    View v;
    v.position = {0, 1, 0};
    v.direction = glm::normalize(glm::vec3(0, -0.35f, -1));
    v.up = {0, 1, 0};
    v.horizontalFovDeg = v.verticalFovDeg = 50.0f;
    return v;
}

ImageRGB render(const Scene& scene, int rays, TextureFilter filter, int size) {
    const Tracer tracer(scene);
    TraceSettings t;
    t.width = t.height = size;
    t.shading.textureFilter = filter;
    StrategySettings s;
    s.name = "uniform";
    s.strata = rays;
    return tracer.render(floorView(), t, s).image;
}

struct Errors {
    double rms = 0.0, max = 0.0;
};

// Errors of `a` against `reference` over rows [firstRow, size), luminance-free: the red channel.
Errors errors(const ImageRGB& a, const ImageRGB& reference, int firstRow) {
    Errors e;
    int n = 0;
    for (int y = firstRow; y < a.height(); ++y)
        for (int x = 0; x < a.width(); ++x) {
            const double d = static_cast<double>(a.at(x, y).r) - reference.at(x, y).r;
            e.rms += d * d;
            e.max = std::max(e.max, std::abs(d));
            ++n;
        }
    e.rms = std::sqrt(e.rms / std::max(n, 1));
    return e;
}

// The first row whose pixels all see the floor (the far edge is above it) with a margin of 2.
int firstFloorRow(const ImageRGB& image) {
    for (int y = image.height() - 1; y >= 0; --y)
        for (int x = 0; x < image.width(); ++x)
            if (!(image.at(x, y).r > 0.0f)) return y + 3;
    return 0;
}

TEST(TextureFiltering, OneFilteredRayMatchesManyRaysOnAMinifiedTexture) {
    // 1024^2 texels, 8 repeats over 24 x 24 scene units: 64x64 pixels each span many texels.
    const Scene scene = texturedFloor(1024, 8.0f, 12.0f, 24.0f);
    constexpr int kSize = 64;
    // The reference takes no filtering on trust: 256 point-sampled rays per pixel.
    const ImageRGB reference = render(scene, 16, TextureFilter::None, kSize);
    const int first = firstFloorRow(reference);
    ASSERT_LT(first, kSize / 2) << "the floor should fill most of the image";
    const Errors filtered = errors(render(scene, 1, TextureFilter::Anisotropic, kSize), reference, first);
    const Errors unfiltered = errors(render(scene, 1, TextureFilter::None, kSize), reference, first);
    // One point sample of the checks is 0.05 or 0.95 against a mean near 0.5: it aliases.
    EXPECT_GT(unfiltered.rms, 0.1) << "the scene does not alias without filtering";
    // Filtered, one ray is within a few per cent of the 256-ray average everywhere.
    EXPECT_LT(filtered.rms, 0.02) << "unfiltered: rms " << unfiltered.rms;
    EXPECT_LT(filtered.max, 0.08);
}

TEST(TextureFiltering, AMagnifiedTextureIsLookedUpAsWithoutFiltering) {
    // 16^2 texels of 1.5 x 1.5 scene units: in the image's lower half (the floor within 3 units of
    // the camera) a pixel's footprint is under 0.2 units, below a texel.
    const Scene scene = texturedFloor(16, 1.0f, 12.0f, 24.0f);
    const ImageRGB filtered = render(scene, 2, TextureFilter::Anisotropic, 48);
    const ImageRGB plain = render(scene, 2, TextureFilter::None, 48);
    for (int y = filtered.height() / 2; y < filtered.height(); ++y)
        for (int x = 0; x < filtered.width(); ++x) ASSERT_EQ(filtered.at(x, y), plain.at(x, y)) << x << "," << y;
}

TEST(TextureFiltering, MipLevelsKeepTheMeanAndHalveTheSides) {
    // Odd sides too: every level is an exact area average, so each keeps the texture's mean.
    std::vector<glm::vec3> rgb(13 * 7);
    double mean = 0.0;
    for (std::size_t i = 0; i < rgb.size(); ++i) {
        rgb[i] = glm::vec3(static_cast<float>((i * 37) % 11) / 10.0f);
        mean += rgb[i].r;
    }
    mean /= static_cast<double>(rgb.size());
    const std::vector<MipLevel> chain = buildMipChain(13, 7, rgb);
    ASSERT_EQ(chain.size(), 4u);  // 13x7, 6x3, 3x1, 1x1
    EXPECT_EQ(chain[1].width, 6);
    EXPECT_EQ(chain[1].height, 3);
    EXPECT_EQ(chain[2].width, 3);
    EXPECT_EQ(chain[2].height, 1);
    for (const MipLevel& level : chain) {
        double m = 0.0;
        for (const glm::vec3& c : level.rgb) m += c.r;
        EXPECT_NEAR(m / static_cast<double>(level.rgb.size()), mean, 1e-5) << level.width << "x" << level.height;
    }
}

TEST(TextureFiltering, FootprintProbesFollowTheMajorAxis) {
    // Isotropic, 4 texels wide: one probe at level 2.
    FootprintProbes p = footprintProbes({4, 0}, {0, 4}, 11);
    EXPECT_EQ(p.count, 1);
    EXPECT_FLOAT_EQ(p.level, 2.0f);
    // 32 x 2 texels: 16 probes 2 texels apart along the major axis, each 2 texels wide (level 1).
    p = footprintProbes({0, 2}, {32, 0}, 11);
    EXPECT_EQ(p.count, 16);
    EXPECT_FLOAT_EQ(p.step.x, 2.0f);
    EXPECT_FLOAT_EQ(p.level, 1.0f);
    // Beyond the anisotropy limit the probes widen: 256 x 2 is 16 probes 16 texels wide.
    p = footprintProbes({256, 0}, {0, 2}, 11);
    EXPECT_EQ(p.count, kMaxTextureAnisotropy);
    EXPECT_FLOAT_EQ(p.level, 4.0f);
    // Below a texel: the plain bilinear lookup.
    p = footprintProbes({0.5f, 0}, {0, 0.1f}, 11);
    EXPECT_EQ(p.count, 1);
    EXPECT_EQ(p.level, 0.0f);
    // Wider than the texture: its average, the last level.
    p = footprintProbes({5000, 0}, {0, 5000}, 11);
    EXPECT_EQ(p.level, 10.0f);
}

TEST(TextureFiltering, BilinearTapsRepeatTheTextureAndStayInsideItAtAnyCoordinate) {
    // Texel (i, j) of a 5 x 3 grid sits at st = ((i + 0.5) / 5, (j + 0.5) / 3): a lookup there is
    // that texel (up to the rounding of st), and shifting st by whole periods, either way, finds
    // the same one. Each texel holds its own index.
    constexpr int kW = 5, kH = 3;
    MipLevel level{kW, kH, {}};
    for (int k = 0; k < kW * kH; ++k) level.rgb.emplace_back(static_cast<float>(k));
    const PackedLevel packed(level, TexelEncoding::Float);
    for (int period : {-1000, -3, -1, 0, 1, 2, 77})
        for (int j = 0; j < kH; ++j)
            for (int i = 0; i < kW; ++i) {
                const glm::vec2 st((i + 0.5f) / kW + static_cast<float>(period), (j + 0.5f) / kH - static_cast<float>(period));
                EXPECT_NEAR(bilinear(packed, st).x, static_cast<float>(j * kW + i), 0.01f) << period << " " << i << " " << j;
            }
    // Between the last column and the first: the right neighbour of column 4 is column 0.
    BilinearTaps t;
    ASSERT_TRUE(bilinearTaps({1.0f, 0.5f / kH}, kW, kH, t));
    EXPECT_EQ(t.i00, 4u);
    EXPECT_EQ(t.i10, 0u);
    EXPECT_FLOAT_EQ(t.ax, 0.5f);
    // Far outside (coordinates a texture never has, but a file can hold): in range, never a crash.
    for (float far : {1e7f + 0.3f, -1e7f, 3e30f, -3e30f}) {
        ASSERT_TRUE(bilinearTaps({far, -far}, kW, kH, t));
        for (std::size_t k : {t.i00, t.i10, t.i01, t.i11}) EXPECT_LT(k, static_cast<std::size_t>(kW * kH)) << far;
    }
    // Where st times the side overflows, or st is not finite, there is no lookup.
    EXPECT_FALSE(bilinearTaps({std::numeric_limits<float>::max(), 0.5f}, kW, kH, t));
    EXPECT_FALSE(bilinearTaps({std::numeric_limits<float>::infinity(), 0.5f}, kW, kH, t));
    EXPECT_FALSE(bilinearTaps({0.5f, std::nanf("")}, kW, kH, t));
}

TEST(TextureFiltering, BounceFootprintKeepsTheMeanOfIndirectLightFromATexture) {
    // A white ceiling seen from below, lit by a point light and by what a checkerboard floor
    // reflects up: path mode with the bounce footprint (the floor filtered over a share of each
    // bounce's lobe, coarse mip levels) and without it (the floor's own texels) agree in mean,
    // since every mip level keeps the texture's mean.
    Scene scene = texturedFloor(64, 2.0f, 4.0f, 8.0f);
    scene.directionalLights.clear();
    // Checks of 8 x 8 texels (0.5 m on the floor): a camera pixel's footprint there sees one or two,
    // a bounce's several.
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x) {
            float* p = &scene.textures[0].rgba[4 * (static_cast<std::size_t>(y) * 64 + static_cast<std::size_t>(x))];
            p[0] = p[1] = p[2] = (x / 8 + y / 8) % 2 == 0 ? 0.95f : 0.05f;
        }
    Material ceiling;
    ceiling.name = "ceiling";
    ceiling.kd = glm::vec3(0.8f);
    scene.materials.push_back(ceiling);
    TriangleMesh& mesh = scene.mesh;
    const auto base = static_cast<std::uint32_t>(mesh.positions.size());
    for (const glm::vec3& p : {glm::vec3(-4, 2, 0), glm::vec3(-4, 2, -8), glm::vec3(4, 2, -8), glm::vec3(4, 2, 0)}) {
        mesh.positions.push_back(p);
        mesh.normals.emplace_back(0, -1, 0);
        mesh.uvs.emplace_back(0, 0);
    }
    mesh.triangles.push_back({base, base + 1, base + 2});
    mesh.triangles.push_back({base, base + 2, base + 3});
    mesh.materialIds.insert(mesh.materialIds.end(), {1, 1});
    mesh.objectIds.insert(mesh.objectIds.end(), {1, 1});
    PointLight lamp;
    lamp.name = "lamp";
    lamp.position = {0, 1, -4};
    lamp.intensity = glm::vec3(4.0f);
    scene.pointLights.push_back(lamp);
    View up;
    up.position = {0, 0.2f, -4};
    up.direction = {0, 1, 0};
    up.up = {0, 0, -1};
    up.horizontalFovDeg = up.verticalFovDeg = 90.0f;

    const Tracer tracer(scene);
    const auto meanRed = [&](float footprint) {
        TraceSettings t;
        t.width = t.height = 32;
        t.shading.mode = ShadingMode::Path;
        t.shading.maxDepth = 3;  // the ceiling, the floor, the light: one bounce off the texture
        t.shading.bounceFootprint = footprint;
        StrategySettings st;
        st.name = "uniform";
        st.strata = 8;
        const ImageRGB image = tracer.render(up, t, st).image;
        double sum = 0.0;
        for (const glm::vec3& c : image.pixels()) sum += c.r;
        return sum / static_cast<double>(image.pixels().size());
    };
    const double texels = meanRed(0.0f), filtered = meanRed(0.25f);
    ASSERT_GT(texels, 0.0);
    EXPECT_NE(texels, filtered);  // the key reaches the lookups
    EXPECT_NEAR(filtered / texels, 1.0, 0.005);
}

}  // namespace
}  // namespace aamap
