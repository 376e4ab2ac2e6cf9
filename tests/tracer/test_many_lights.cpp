// Many-light direct lighting (more than LightSet::kFewLights): the per-hit contribution CDF
// (LightSelection::Contribution) against the global power CDF and against the exact per-light
// estimator, plus the bounds LightSet::contribution must keep to stay unbiased.
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "tests/tracer/material_scenes.h"
#include "tracer/embree_scene.h"
#include "tracer/lights.h"

namespace aamap {
namespace {

using testing::lookAt;
using testing::renderScene;

constexpr int kLights = 12;

// A plane lit by 12 lights: a small dim quad just above the viewed spot (it dominates there but
// has little power), and 11 large bright far lights (two of them points, one with a cosine
// lobe). `only` >= 0 keeps one light emitting; the other quads stay as black occluders.
Scene dominantNearLightScene(int only) {
    testing::SceneBuilder b;
    b.quad({-30, 0, -30}, {0, 0, 60}, {60, 0, 0}, b.material("plane", glm::vec3(0.6f)));
    const auto black = b.material("black", glm::vec3(0.0f));
    for (int i = 0; i < kLights; ++i) {
        const bool on = only < 0 || i == only;
        glm::vec3 p0, a, c, le;
        if (i == 0) {  // the near light, faces down
            p0 = {-0.1f, 0.3f, -0.1f}, a = {0.2f, 0, 0}, c = {0, 0, 0.2f}, le = glm::vec3(4.0f, 3.0f, 2.0f);
        } else {  // far and strong, faces down
            const float x = -10.0f + 2.0f * static_cast<float>(i);
            p0 = {x, 6.0f, -9.0f}, a = {1.5f, 0, 0}, c = {0, 0, 1.5f}, le = glm::vec3(6.0f, 6.0f + 0.3f * i, 5.0f);
        }
        if (i == 5 || i == 9) {
            if (on) b.pointLight(p0, le * 3.0f, i == 9 ? glm::vec3(0, -1, 0.3f) : glm::vec3(0.0f));
        } else if (on) {
            b.areaLightQuad(p0, a, c, le);
        } else {
            b.quad(p0, a, c, black);
        }
    }
    return std::move(b.scene());
}

const View kView = lookAt({0, 2.0f, 2.2f}, {0, 0, 0}, 50);
constexpr int kImageSize = 24;

// The exact answer's estimate: the sum of one-light renders (each the few-lights estimator).
std::vector<glm::dvec3> sumOfSingleLights(int samples) {
    ShadingSettings sh;
    sh.areaLightSamples = samples;
    std::vector<glm::dvec3> sum(static_cast<std::size_t>(kImageSize * kImageSize), glm::dvec3(0.0));
    for (int i = 0; i < kLights; ++i) {
        const TraceResult one = renderScene(dominantNearLightScene(i), kView, sh, kImageSize, 1);
        for (std::size_t k = 0; k < sum.size(); ++k) sum[k] += glm::dvec3(one.image.pixels()[k]);
    }
    return sum;
}

TraceResult renderAll(LightSelection selection, int samples, std::uint64_t seed = 5) {
    ShadingSettings sh;
    sh.areaLightSamples = samples;
    sh.lightSelection = selection;
    return renderScene(dominantNearLightScene(-1), kView, sh, kImageSize, 1, 0, seed);
}

double rmsError(const TraceResult& r, const std::vector<glm::dvec3>& ref) {
    double s = 0.0;
    for (std::size_t k = 0; k < ref.size(); ++k) {
        const glm::dvec3 d = glm::dvec3(r.image.pixels()[k]) - ref[k];
        s += glm::dot(d, d);
    }
    return std::sqrt(s / static_cast<double>(ref.size()));
}

// Superposition: the per-hit CDF's image matches the sum of single-light renders, per channel,
// within 4 standard errors of the per-pixel differences (seed 5 shares the reference's primary
// rays; other seeds add their pixel jitter to the per-pixel spread). Three seeds: a fixed-pattern
// bias (e.g. an unrandomised permutation of the light-sample strata) shows up in every one.
TEST(ManyLights, ContributionSelectionIsUnbiased) {
    const std::vector<glm::dvec3> ref = sumOfSingleLights(256);
    for (std::uint64_t seed : {5u, 6u, 7u}) {
        const TraceResult many = renderAll(LightSelection::Contribution, 16, seed);
        EXPECT_EQ(many.nonFiniteSamples, 0u);
        for (int c = 0; c < 3; ++c) {
            std::vector<double> diff, signal;
            for (std::size_t k = 0; k < ref.size(); ++k) {
                diff.push_back(many.image.pixels()[k][c] - ref[k][c]);
                signal.push_back(ref[k][c]);
            }
            const auto [mean, error] = testing::meanError(diff);
            const double level = testing::meanError(signal).mean;
            EXPECT_LT(4 * error, 0.05 * level) << "too noisy to test, channel " << c;
            EXPECT_NEAR(mean, 0.0, 4 * error + 1e-4 * level) << "channel " << c << ", seed " << seed;
        }
    }
}

// The point of the per-hit CDF: with one nearby light dominating, the global power CDF spends
// almost every sample on bright far lights. Same sample count, at least 2x lower RMS error.
TEST(ManyLights, ContributionSelectionBeatsPowerSelection) {
    const std::vector<glm::dvec3> ref = sumOfSingleLights(1024);
    const double power = rmsError(renderAll(LightSelection::Power, 16), ref);
    const double contribution = rmsError(renderAll(LightSelection::Contribution, 16), ref);
    RecordProperty("rms_power", std::to_string(power));
    RecordProperty("rms_contribution", std::to_string(contribution));
    EXPECT_LT(2.0 * contribution, power) << "power " << power << ", contribution " << contribution;
}

TEST(ManyLights, ContributionSelectionIsDeterministicAcrossThreads) {
    ShadingSettings sh;
    const Scene scene = dominantNearLightScene(-1);
    const TraceResult a = renderScene(scene, kView, sh, 16, 2, 1);
    const TraceResult b = renderScene(scene, kView, sh, 16, 2, 4);
    EXPECT_EQ(a.image.pixels(), b.image.pixels());
    EXPECT_EQ(a.rays.total(), b.rays.total());
}

// Up to kFewLights the setting changes nothing: every light is taken at every hit.
TEST(ManyLights, FewLightImagesIgnoreTheSelectionSetting) {
    const Scene scene = testing::cornellLikeScene();
    ShadingSettings power, contribution;
    power.lightSelection = LightSelection::Power;
    contribution.lightSelection = LightSelection::Contribution;
    const TraceResult a = renderScene(scene, scene.views.front(), power, 24, 2);
    const TraceResult b = renderScene(scene, scene.views.front(), contribution, 24, 2);
    EXPECT_EQ(a.image.pixels(), b.image.pixels());
}

// The bound is 0 only when no point of the light can reach the receiver from above its normal.
TEST(ManyLights, ContributionBoundNeverZeroWhereTheLightReaches) {
    testing::SceneBuilder b;
    // Vertical quad at x = 2 facing -x, y in [-1, 0.5]: its centroid is below the horizon of a
    // receiver at the origin with normal +y, but its top part is above it.
    b.areaLightQuad({2, -1, -1}, {0, 0, 2}, {0, 1.5f, 0}, glm::vec3(1.0f));
    // Entirely below that horizon.
    b.areaLightQuad({3, -2, -1}, {0, 0, 2}, {0, 1.0f, 0}, glm::vec3(1.0f));
    // Faces away from the origin (+x).
    b.areaLightQuad({4, 0, -1}, {0, 1.0f, 0}, {0, 0, 2}, glm::vec3(1.0f));
    const EmbreeScene geometry(b.scene());
    const LightSet lights = buildLights(b.scene(), geometry);
    ASSERT_EQ(lights.count(), 3u);
    const glm::vec3 x(0.0f), n(0, 1, 0);
    EXPECT_GT(lights.contribution(0, x, n), 0.0f);
    EXPECT_EQ(lights.contribution(1, x, n), 0.0f);
    EXPECT_EQ(lights.contribution(2, x, n), 0.0f);
    // Inside the bounding sphere, any side: positive, at most the cap pi L. Right in front of the
    // light and facing it, the polygon estimate: nearly the whole hemisphere, so nearly pi L.
    const glm::vec3 inside(2.0f, -0.25f, 0.0f);
    const float sideways = lights.contribution(0, inside - glm::vec3(0.01f, 0, 0), glm::vec3(0, 0, 1));
    EXPECT_GT(sideways, 0.0f);
    EXPECT_LE(sideways, 3.14159265f);
    const float facing = lights.contribution(0, inside - glm::vec3(0.01f, 0, 0), glm::vec3(1, 0, 0));
    EXPECT_GT(facing, 0.98f * 3.14159265f);
    EXPECT_LE(facing, 3.14159265f);
}

}  // namespace
}  // namespace aamap
