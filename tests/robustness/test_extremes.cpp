// Numerical extremes of the tracer and the CPU aamap filter chain: every image finite and sensible
// at the limits users push parameters to. Each test checks a property with a known
// answer (linearity, scale invariance, exact constants), not stored outputs.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <unistd.h>

#include "core/image_io.h"
#include "passes/cpu_aamap.h"
#include "tests/tracer/scene_builder.h"
#include "tracer/tracer.h"

namespace aamap {
namespace {
namespace fs = std::filesystem;

TraceSettings settings(int width, int height, int threads = 0) {
    TraceSettings s;
    s.width = width;
    s.height = height;
    s.threads = threads;
    s.shading.areaLightSamples = 4;
    return s;
}

StrategySettings uniform(int strata) {
    StrategySettings s;
    s.name = "uniform";
    s.strata = strata;
    return s;
}

void expectFinite(const TraceResult& r) {
    ASSERT_EQ(r.image.width() * r.image.height(), r.primaryRays.width() * r.primaryRays.height());
    for (const glm::vec3& p : r.image.pixels()) {
        ASSERT_TRUE(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z));
        ASSERT_GE(std::min({p.x, p.y, p.z}), 0.0f);
    }
}

double meanLuminance(const ImageRGB& image) {
    double sum = 0.0;
    for (const glm::vec3& p : image.pixels()) sum += (p.x + p.y + p.z) / 3.0;
    return sum / static_cast<double>(image.pixels().size());
}

Scene scaledCornell(float scale, float emission = 1.0f) {
    Scene scene = testing::cornellLikeScene();
    for (glm::vec3& p : scene.mesh.positions) p *= scale;
    for (AreaLight& light : scene.areaLights) {
        light.area *= scale * scale;
        light.radiance *= emission;
    }
    for (Material& m : scene.materials) m.ke *= emission;
    for (View& v : scene.views) v.position *= scale;
    return scene;
}

class Extremes : public testing::CornellTracerTest {};

TEST_F(Extremes, RaysPerPixel1And1024) {
    const TraceResult one = tracer_->render(view(), settings(16, 16), uniform(1));
    const TraceResult many = tracer_->render(view(), settings(16, 16), uniform(32));  // 32 x 32 = 1024
    expectFinite(one);
    expectFinite(many);
    for (std::uint16_t r : one.primaryRays.pixels()) EXPECT_EQ(r, 1);
    for (std::uint16_t r : many.primaryRays.pixels()) EXPECT_EQ(r, 1024);
    // The same scene: the 1-ray image is a noisier estimate of the same mean.
    EXPECT_NEAR(meanLuminance(one.image), meanLuminance(many.image), 0.1 * meanLuminance(many.image));
}

TEST_F(Extremes, ImageSizes1x1And3x7) {
    for (const auto& [w, h] : {std::pair{1, 1}, std::pair{3, 7}, std::pair{7, 3}}) {
        const TraceResult r = tracer_->render(view(), settings(w, h), uniform(2));
        EXPECT_EQ(r.image.width(), w);
        EXPECT_EQ(r.image.height(), h);
        expectFinite(r);
        EXPECT_GT(meanLuminance(r.image), 0.0);
    }
}

// 2048 x 2048 at 1 ray per pixel, every pixel traced: the largest size that stays within seconds on
// CI's 2 cores. Budget: 4 Mpx x (12 B RGB + 2 B rays + 1 B traced) = 60 MiB of images. 8192 x 8192
// follows, by subsampling.
TEST_F(Extremes, LargeImage2048) {
    TraceSettings s = settings(2048, 2048);
    s.shading.areaLightSamples = 1;
    const TraceResult r = tracer_->render(view(), s, uniform(1));
    EXPECT_EQ(r.image.width(), 2048);
    expectFinite(r);
    EXPECT_EQ(r.rays.primary, 2048u * 2048u);
}

// 8192 x 8192, the largest supported size, through the cheapest strategy that still writes every
// pixel: aamap-subsample with s = 64, t = infinity and no gradient rounds traces only the grid
// (129 x 129 rays, one per grid pixel) and interpolates the rest. Budget, stated up front: 64 Mpx x (12 B RGB + 2 B rays
// + 1 B traced + 4 B aamap + 12 B block sums: a double table and a uint32 count table) = 1.9 GiB
// (peak RSS and time: docs/robustness.md). Every pixel must be finite, and the interpolation
// between finite corners must stay within their range.
TEST_F(Extremes, LargeImage8192BySubsampling) {
    constexpr int kSize = 8192;
    const ImageGrey map(kSize, kSize, 0.0f);
    StrategySettings st;
    st.name = "aamap-subsample";
    st.strata = 1;
    st.aamap = &map;
    st.params.set("spacing", 64);
    st.params.set("threshold", std::numeric_limits<double>::infinity());
    st.params.set("gradient_tolerance", std::numeric_limits<double>::infinity());  // no gradient rounds
    TraceSettings s = settings(kSize, kSize);
    s.shading.areaLightSamples = 1;
    const TraceResult r = tracer_->render(view(), s, st);
    ASSERT_EQ(r.image.width(), kSize);
    ASSERT_EQ(r.image.height(), kSize);
    expectFinite(r);
    const std::uint64_t gridLines = kSize / 64 + 1;  // 0, 64, ..., 8128, and the last pixel 8191
    EXPECT_EQ(r.rays.primary, gridLines * gridLines);
    std::uint64_t traced = 0;
    for (std::uint8_t t : r.traced.pixels()) traced += t;
    EXPECT_EQ(traced, gridLines * gridLines);
    float tracedMax = 0.0f;
    for (int y = 0; y < kSize; y += 64)
        for (int x = 0; x < kSize; x += 64) tracedMax = std::max({tracedMax, r.image.at(x, y).x, r.image.at(x, y).y, r.image.at(x, y).z});
    for (const glm::vec3& p : r.image.pixels()) ASSERT_LE(std::max({p.x, p.y, p.z}), tracedMax * (1.0f + 1e-6f) + 1e-30f);
}

TEST_F(Extremes, SubsampleSpacing1AndLargerThanTheImage) {
    const int w = 24, h = 16;
    ImageGrey map(w, h, 0.0f);
    for (int y = 0; y < h; ++y) map.at(w / 2, y) = 1.0f;  // one vertical edge
    for (int spacing : {1, 2, 32, 64}) {
        StrategySettings st;
        st.name = "aamap-subsample";
        st.strata = 4;
        st.aamap = &map;
        st.params.set("spacing", spacing);
        const TraceResult r = tracer_->render(view(), settings(w, h), st);
        expectFinite(r);
        // Every pixel on the marked edge is traced with k = n strata.
        for (int y = 0; y < h; ++y) EXPECT_EQ(r.primaryRays.at(w / 2, y), 16) << "spacing " << spacing;
    }
}

TEST_F(Extremes, ThresholdZeroAndInfinity) {
    const int w = 24, h = 16;
    ImageGrey map(w, h, 0.25f);
    for (const std::string kind : {"aamap-subsample", "rpict"}) {
        for (double threshold : {0.0, std::numeric_limits<double>::infinity()}) {
            StrategySettings st;
            st.name = kind;
            st.strata = 2;
            st.aamap = &map;
            st.params.set("spacing", 4);
            st.params.set("threshold", threshold);
            const TraceResult r = tracer_->render(view(), settings(w, h), st);
            expectFinite(r);
            EXPECT_GT(r.rays.primary, 0u);
        }
    }
}

// Radiance is invariant under a uniform scaling of the scene, its lights and the camera: the same
// seed gives the same samples, so images agree up to the self-intersection offsets.
TEST(ExtremesScale, SceneScale1em4To1e6) {
    Scene reference = scaledCornell(1.0f);
    const Tracer referenceTracer(reference);
    const TraceResult base = referenceTracer.render(reference.views.front(), settings(24, 24), uniform(2));
    for (float scale : {1e-4f, 1e-2f, 1e3f, 1e6f}) {
        const Scene scene = scaledCornell(scale);
        const Tracer tracer(scene);
        const TraceResult r = tracer.render(scene.views.front(), settings(24, 24), uniform(2));
        expectFinite(r);
        EXPECT_NEAR(meanLuminance(r.image), meanLuminance(base.image), 0.02 * meanLuminance(base.image)) << scale;
        EXPECT_EQ(r.nonFiniteSamples, 0u) << scale;
    }
}

// Direct shading is linear in emission: the same seed, every sample scales by the same factor.
TEST(ExtremesEmission, Emission1em6To1e6IsLinear) {
    Scene reference = scaledCornell(1.0f);
    const Tracer referenceTracer(reference);
    const double base = meanLuminance(referenceTracer.render(reference.views.front(), settings(16, 16), uniform(2)).image);
    for (float emission : {1e-6f, 1e-3f, 1e3f, 1e6f}) {
        const Scene scene = scaledCornell(1.0f, emission);
        const Tracer tracer(scene);
        const TraceResult r = tracer.render(scene.views.front(), settings(16, 16), uniform(2));
        expectFinite(r);
        EXPECT_NEAR(meanLuminance(r.image) / emission, base, 1e-4 * base) << emission;
    }
}

// A camera inside a closed emissive box of constant radiance L and kd = 0 sees exactly L from
// every sample: the average of 1024 samples per pixel must still be L (no accumulation drift).
TEST(ExtremesAccumulation, ThousandSamplesDoNotDrift) {
    testing::SceneBuilder b;
    const glm::vec3 L(0.1f, 1.0f / 3.0f, 12345.678f);
    const auto glow = b.material("glow", glm::vec3(0.0f), L);
    b.box({-1, -1, -1}, {1, 1, 1}, glow);
    Scene scene = std::move(b.scene());
    // Seen from inside, the box's outward faces are back faces; emission there is zero for a
    // one-sided emitter, so flip the winding to face inwards.
    for (glm::uvec3& t : scene.mesh.triangles) std::swap(t.y, t.z);
    for (glm::vec3& n : scene.mesh.normals) n = -n;
    View view;
    view.position = glm::vec3(0.0f);
    view.direction = {0, 0, -1};
    const Tracer tracer(scene);
    TraceSettings s = settings(4, 4);
    const TraceResult r = tracer.render(view, s, uniform(32));
    for (const glm::vec3& p : r.image.pixels()) {
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(p[c], L[c], 1e-6 * L[c]) << "channel " << c;
    }
}

// An infinite emitter makes every sample that sees it non-finite: counted, never written.
TEST(ExtremesNonFinite, InfiniteEmissionIsCountedNotWritten) {
    Scene scene = scaledCornell(1.0f, std::numeric_limits<float>::infinity());
    const Tracer tracer(scene);
    const TraceResult r = tracer.render(scene.views.front(), settings(16, 16), uniform(2));
    expectFinite(r);
    EXPECT_GT(r.nonFiniteSamples, 0u);
}

std::string fileBytes(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// The written files, not just the pixels, are identical for 1, 2 and 16 threads.
TEST_F(Extremes, OutputsBitIdenticalFor1And2And16Threads) {
    const fs::path dir = fs::temp_directory_path() / ("aamap_threads_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    ImageGrey map(40, 30, 0.0f);
    for (int y = 0; y < 30; ++y) map.at(20, y) = 1.0f;
    std::vector<std::string> exr, png;
    for (int threads : {1, 2, 16}) {
        for (const std::string kind : {"uniform", "aamap-subsample"}) {
            StrategySettings st = uniform(3);
            st.name = kind;
            st.aamap = &map;
            const TraceResult r = tracer_->render(view(), settings(40, 30, threads), st);
            const fs::path base = dir / (kind + std::to_string(threads));
            writeExr(base.string() + ".exr", r.image);
            writePng(base.string() + ".png", toneMap(r.image));
            exr.push_back(fileBytes(base.string() + ".exr"));
            png.push_back(fileBytes(base.string() + ".png"));
        }
    }
    std::error_code ec;
    fs::remove_all(dir, ec);
    for (std::size_t i = 2; i < exr.size(); ++i) {
        EXPECT_EQ(exr[i], exr[i % 2]) << "run " << i;
        EXPECT_EQ(png[i], png[i % 2]) << "run " << i;
    }
}

// --- the CPU aamap filter chain (the GPU chain is tested against it within 1e-5) ---

// A constant image has no edges: the aamap is exactly 0, at any level, however bright or dark.
TEST(ExtremesAamap, ConstantImageGivesExactlyZero) {
    for (float level : {0.0f, 1e-30f, 1e-6f, 0.5f, 1.0f, 1e6f, 1e30f, std::numeric_limits<float>::max()}) {
        const ImageRGB snapshot(48, 36, glm::vec3(level));
        const cpu::AamapImages out = cpu::buildAamap(snapshot, 32, 24, FilterParams{});
        for (float a : out.aamap.pixels()) ASSERT_EQ(a, 0.0f) << level;
        for (float l : out.laplacian.pixels()) ASSERT_EQ(l, 0.0f) << level;
    }
}

// Luminance spanning 12 orders of magnitude (1e-6 .. 1e6, log ramp plus a checker): the aamap is
// finite, in [0, 1], and stable -- a 0.1% change of the input moves it by at most 0.01. The
// greyscale step is the display encoding of the clamped value (sRGB(clamp(exposure * rgb, 0, 1))),
// so everything above 1 saturates to the same grey and the map cannot blow up.
TEST(ExtremesAamap, TwelveOrdersOfMagnitudeStayStable) {
    const int w = 96, h = 64;
    ImageRGB snapshot(w, h), perturbed(w, h);
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            const float ramp = std::pow(10.0f, -6.0f + 12.0f * static_cast<float>(x) / (w - 1));
            const float checker = ((x / 8 + y / 8) % 2) ? 1.0f : 0.5f;
            snapshot.at(x, y) = glm::vec3(ramp * checker);
            perturbed.at(x, y) = glm::vec3(ramp * checker * (1.0f + 1e-3f * static_cast<float>((x * 7 + y * 3) % 3 - 1)));
        }
    }
    const auto a = cpu::buildAamap(snapshot, 64, 42, FilterParams{});
    const auto b = cpu::buildAamap(perturbed, 64, 42, FilterParams{});
    float maxDiff = 0.0f;
    for (std::size_t i = 0; i < a.aamap.pixels().size(); ++i) {
        const float va = a.aamap.pixels()[i], vb = b.aamap.pixels()[i];
        ASSERT_TRUE(std::isfinite(va) && va >= 0.0f && va <= 1.0f);
        maxDiff = std::max(maxDiff, std::abs(va - vb));
    }
    EXPECT_LE(maxDiff, 0.01f);
    // The saturated end (input >= 2, every texel clamps to 1) has no edges at all.
    for (int y = 0; y < 42; ++y) EXPECT_EQ(a.aamap.at(63, y), 0.0f) << y;
}

}  // namespace
}  // namespace aamap
