// Direct mode's glossy lobes (docs/tracer.md, "Glossy lobes in direct and cache modes"): BSDF
// samples of the glossy lobe MIS-weighted against the light samples, and the glossy reflection
// of the scene. Checked against path mode with a depth that computes exactly what direct mode
// does, by the variance MIS removes, and by thread-count determinism.
#include <cmath>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "tests/tracer/material_scenes.h"
#include "tracer/tracer.h"

namespace aamap {
namespace {

using testing::lookAt;
using testing::renderScene;

Material roughPlane(BsdfModel model, float alpha) {
    Material m;
    m.name = "plane";
    m.model = model;
    m.distribution = MicrofacetType::GGX;
    m.alphaU = m.alphaV = alpha;
    m.kd = glm::vec3(0.5f, 0.35f, 0.2f);
    m.ior = 1.5f;
    m.eta = glm::vec3(0.2f, 0.9f, 1.1f);  // copper-like
    m.k = glm::vec3(3.9f, 2.4f, 2.1f);
    return m;
}

// Path mode against direct mode on the same primary rays, per pixel over the rows [rowFrom, size):
// the mean difference within 4 standard errors of the per-pixel differences, and those errors
// small enough (under 5 % of the signal) for the comparison to mean something.
void expectPathMatchesDirect(const Scene& scene, const View& view, int maxDepth, int rowFrom, int size, int strata) {
    ShadingSettings direct;
    direct.areaLightSamples = 64;
    ShadingSettings path;
    path.mode = ShadingMode::Path;
    path.maxDepth = maxDepth;
    const TraceResult d = renderScene(scene, view, direct, size, strata);
    const TraceResult p = renderScene(scene, view, path, size, strata);
    ASSERT_EQ(d.nonFiniteSamples, 0u);
    for (int c = 0; c < 3; ++c) {
        std::vector<double> diff, ref;
        for (int y = rowFrom; y < size; ++y)
            for (int x = 0; x < size; ++x) {
                diff.push_back(p.image.at(x, y)[c] - d.image.at(x, y)[c]);
                ref.push_back(d.image.at(x, y)[c]);
            }
        const auto [mean, error] = testing::meanError(diff);
        const double signal = testing::meanError(ref).mean;
        EXPECT_LT(4 * error, 0.05 * signal) << "channel " << c;
        EXPECT_NEAR(mean, 0.0, 4 * error + 1e-4 * signal) << "channel " << c << " (signal " << signal << ")";
    }
}

// A rough plane under a small area light and nothing else: path mode with max_depth 2 is direct
// light alone (its NEE and the BSDF samples that hit the light, MIS-weighted), which direct mode
// computes with its light samples and glossy samples (MIS-weighted the other way).
void expectHighlightMatchesPath(const Material& plane) {
    testing::SceneBuilder b;
    b.quad({-20, 0, -20}, {0, 0, 40}, {40, 0, 0}, testing::addMaterial(b, plane));
    b.areaLightQuad({-0.15f, 1.0f, -0.1f}, {0.3f, 0, 0}, {0, 0, 0.2f}, glm::vec3(40.0f, 30.0f, 20.0f));  // faces down
    expectPathMatchesDirect(b.scene(), lookAt({0, 1.0f, 1.6f}, {0, 0, -0.3f}, 50), 2, 0, 32, 8);
}

TEST(GlossyDirect, RoughConductorHighlightMatchesPath) {
    expectHighlightMatchesPath(roughPlane(BsdfModel::Conductor, 0.08f));
}
TEST(GlossyDirect, RoughPlasticHighlightMatchesPath) {
    expectHighlightMatchesPath(roughPlane(BsdfModel::Plastic, 0.1f));
}
TEST(GlossyDirect, PhongHighlightMatchesPath) {
    Material m;
    m.name = "plane";
    m.kd = glm::vec3(0.3f);
    m.ks = glm::vec3(0.5f);
    m.ns = 200.0f;
    expectHighlightMatchesPath(m);
}

// A rough conductor floor reflecting a diffuse wall lit by an area light. Path mode with
// max_depth 3 computes, at the floor, direct light plus one glossy bounce that takes the wall's
// direct light: what direct mode's glossy samples do (the floor has no diffuse part, so nothing
// of path mode's indirect diffuse light is missing). Only rows that see the floor are compared:
// a directly seen wall would get the floor's reflection as indirect light in path mode.
TEST(GlossyDirect, ReflectionOfALitWallMatchesPath) {
    testing::SceneBuilder b;
    b.quad({-20, 0, -20}, {0, 0, 40}, {40, 0, 0}, testing::addMaterial(b, roughPlane(BsdfModel::Conductor, 0.15f)));
    b.quad({-3, 0, -1}, {6, 0, 0}, {0, 4, 0}, b.material("wall", glm::vec3(0.8f, 0.7f, 0.5f)));  // faces +z
    b.areaLightQuad({-0.5f, 2.0f, 0.8f}, {0, 0.6f, 0}, {1.0f, 0, 0}, glm::vec3(20.0f));       // faces -z
    // The view looks down 21.8 degrees with a 60 degree field: its lower 40 % of rows (down to
    // 28 degrees and more) meet the floor in front of the wall.
    const int size = 30;
    expectPathMatchesDirect(b.scene(), lookAt({0, 1.0f, 2.0f}, {0, 0.2f, 0}, 60), 3, size * 6 / 10, size, 6);
}

// shading.glossy_reflection_alpha: a lobe rougher than it takes no glossy samples (its scene
// reflection is left out and the rays are those of light sampling alone), one within it does; a
// Phong exponent n counts as alpha sqrt(2 / (n + 2)).
TEST(GlossyDirect, OnlyLobesWithinTheRoughnessLimitReflectTheScene) {
    const auto otherRays = [](const Material& floor, float limit) {
        testing::SceneBuilder b;
        b.quad({-20, 0, -20}, {0, 0, 40}, {40, 0, 0}, testing::addMaterial(b, floor));
        b.quad({-3, 0, -1}, {6, 0, 0}, {0, 4, 0}, b.material("wall", glm::vec3(0.8f, 0.7f, 0.5f)));
        b.areaLightQuad({-0.5f, 2.0f, 0.8f}, {0, 0.6f, 0}, {1.0f, 0, 0}, glm::vec3(20.0f));
        ShadingSettings sh;
        sh.areaLightSamples = 16;
        sh.glossyReflectionAlpha = limit;
        return renderScene(b.scene(), lookAt({0, 1.0f, 2.0f}, {0, 0.2f, 0}, 60), sh, 16, 1).rays.other;
    };
    const Material conductor = roughPlane(BsdfModel::Conductor, 0.15f);
    EXPECT_GT(otherRays(conductor, 0.2f), 0u);
    EXPECT_EQ(otherRays(conductor, 0.1f), 0u);
    Material phong;
    phong.name = "phong";
    phong.kd = glm::vec3(0.3f);
    phong.ks = glm::vec3(0.5f);
    phong.ns = 40.0f;  // alpha sqrt(2 / 42) = 0.218
    EXPECT_EQ(otherRays(phong, 0.2f), 0u);
    EXPECT_GT(otherRays(phong, 0.25f), 0u);
}

// Per-pixel variance over independent seeds of a low-roughness conductor's highlight: with the
// glossy samples and MIS it must be far below that of the light samples alone (the same light
// samples; max_specular_depth 0 takes no glossy samples), and both must agree in the mean.
TEST(GlossyDirect, MisCutsTheVarianceOfANarrowHighlight) {
    testing::SceneBuilder b;
    b.quad({-20, 0, -20}, {0, 0, 40}, {40, 0, 0}, testing::addMaterial(b, roughPlane(BsdfModel::Conductor, 0.05f)));
    b.areaLightQuad({-0.5f, 1.0f, -0.5f}, {1.0f, 0, 0}, {0, 0, 1.0f}, glm::vec3(5.0f));  // faces down
    const View view = lookAt({0, 1.0f, 1.6f}, {0, 0, -0.3f}, 50);
    const int size = 24, seeds = 8;
    const auto stats = [&](int maxSpecularDepth) {
        ShadingSettings sh;
        sh.maxSpecularDepth = maxSpecularDepth;
        std::vector<double> sum(size * size, 0.0), sum2(size * size, 0.0);
        for (int s = 0; s < seeds; ++s) {
            const TraceResult r = renderScene(b.scene(), view, sh, size, 1, 0, 100 + static_cast<std::uint64_t>(s));
            for (std::size_t i = 0; i < sum.size(); ++i) {
                const double v = r.image.pixels()[i].y;
                sum[i] += v;
                sum2[i] += v * v;
            }
        }
        double variance = 0.0, mean = 0.0;
        for (std::size_t i = 0; i < sum.size(); ++i) {
            const double m = sum[i] / seeds;
            variance += (sum2[i] / seeds - m * m) * seeds / (seeds - 1.0);
            mean += m;
        }
        const double n = static_cast<double>(sum.size());
        return std::pair{mean / n, variance / n};
    };
    const auto [misMean, misVariance] = stats(8);
    const auto [lightMean, lightVariance] = stats(0);
    EXPECT_LT(misVariance, 0.1 * lightVariance) << "MIS " << misVariance << ", light samples alone " << lightVariance;
    // Means of n^2 pixels x seeds estimates each: their difference within the light-only noise.
    const double error = std::sqrt((lightVariance + misVariance) / (size * size * seeds));
    EXPECT_NEAR(misMean, lightMean, 4 * error + 1e-4 * lightMean);
}

// Glossy samples draw from their own sample streams: images stay bit-identical for any thread
// count, in direct and cache modes, with Phong, rough conductor and rough plastic lobes.
TEST(GlossyDirect, BitIdenticalForAnyThreadCount) {
    Scene scene = testing::cornellLikeScene();
    for (std::size_t i = 0; i < scene.materials.size(); ++i) {
        Material& m = scene.materials[i];
        if (m.ke != glm::vec3(0.0f)) continue;
        if (i == 0) {  // white: rough conductor
            m = roughPlane(BsdfModel::Conductor, 0.1f);
        } else if (i == 1) {
            m.model = BsdfModel::Plastic;
            m.distribution = MicrofacetType::Beckmann;
            m.alphaU = m.alphaV = 0.2f;
            m.ior = 1.49f;
        } else {
            m.ks = glm::vec3(0.2f);
            m.ns = 50.0f;
        }
    }
    for (const ShadingMode mode : {ShadingMode::Direct, ShadingMode::Cache}) {
        ShadingSettings sh;
        sh.mode = mode;
        const TraceResult a = renderScene(scene, scene.views.front(), sh, 20, 2, 1);
        const TraceResult c = renderScene(scene, scene.views.front(), sh, 20, 2, 8);
        EXPECT_EQ(a.image.pixels(), c.image.pixels()) << toString(mode);
        EXPECT_EQ(a.rays.total(), c.rays.total()) << toString(mode);
        EXPECT_EQ(a.nonFiniteSamples, 0u);
    }
}

}  // namespace
}  // namespace aamap
