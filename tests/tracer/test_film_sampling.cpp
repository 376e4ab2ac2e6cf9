// Film sampling as a property of whole renders: the k x k primary rays of a pixel land one in each
// of its k x k cells, observed through Tracer::render (the camera, the film-position code and each
// strategy's way of asking for strata), not through the sampler alone. A cell is made visible by
// an emitter whose image covers exactly that cell of that pixel, on a black background: the pixel
// then reads (rays in the cell) / k^2 times the emission, so one ray per cell reads exactly 1 / k^2.
#include <limits>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "scene/camera.h"
#include "tests/tracer/scene_builder.h"
#include "tracer/pixel_filter.h"
#include "tracer/tracer.h"

namespace aamap {
namespace {

// Looks down -z from the origin with a 90 degree field both ways: the film point (u, v) sees the
// point camera.direction(u, v) of the plane z = -1, linearly in u and v.
View frontView() {
    View v;
    v.position = {0, 0, 0};
    v.direction = {0, 0, -1};
    v.up = {0, 1, 0};
    v.horizontalFovDeg = v.verticalFovDeg = 90.0f;
    return v;
}

// An emitter of radiance 1 on z = -1 whose image is the film rectangle [u0, u1] x [v0, v1]
// (film coordinates of the whole image, v down). It faces the camera (+z).
void addFilmRectangle(testing::SceneBuilder& b, double u0, double v0, double u1, double v1) {
    const PinholeCamera camera = PinholeCamera::fromView(frontView());
    const glm::vec3 topLeft = camera.direction(static_cast<float>(u0), static_cast<float>(v0));
    const glm::vec3 bottomRight = camera.direction(static_cast<float>(u1), static_cast<float>(v1));
    const glm::vec3 p0(topLeft.x, bottomRight.y, -1.0f);  // bottom left: v grows downwards
    const glm::vec3 a(bottomRight.x - topLeft.x, 0, 0), b2(0, topLeft.y - bottomRight.y, 0);
    b.areaLightQuad(p0, a, b2, glm::vec3(1.0f));
}

// A size x size image in which pixel (x, y) shows only its cell (x, y) of a size x size grid:
// every cell position of the grid is probed once, by a different pixel.
Scene cellProbeScene(int size) {
    testing::SceneBuilder b;
    const double cell = 1.0 / (static_cast<double>(size) * size);  // a cell, in film units
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            const double u0 = static_cast<double>(x) / size + x * cell;
            const double v0 = static_cast<double>(y) / size + y * cell;
            addFilmRectangle(b, u0, v0, u0 + cell, v0 + cell);
        }
    return std::move(b.scene());
}

struct StratifyingStrategy {
    std::string name;
    StrategySettings settings;
    int grid;  // cells per axis of a pixel that its rays should fill one each
};

// Every strategy that stratifies the film, configured so that every pixel gets all its strata;
// `k` is the strata per axis the pixel should end up with.
std::vector<StratifyingStrategy> stratifyingStrategies(int k, const ImageGrey* ones) {
    std::vector<StratifyingStrategy> all;
    const auto add = [&](const std::string& name, const std::string& kind, auto&& configure) {
        StrategySettings s;
        s.name = kind;
        s.strata = k;
        configure(s);
        all.push_back({name, s, k});
    };
    add("uniform", "uniform", [](StrategySettings&) {});
    add("aamap", "aamap", [&](StrategySettings& s) { s.aamap = ones; });
    add("aamap-linear-rays", "aamap", [&](StrategySettings& s) {
        s.aamap = ones;
        s.params.set("mapping", std::string(toString(StrataMapping::LinearRays)));
    });
    add("aamap-subsample", "aamap-subsample", [&](StrategySettings& s) {
        s.aamap = ones;
        s.params.set("spacing", 1);
        s.params.set("threshold", 0.0);
    });
    add("variance", "variance", [](StrategySettings& s) {
        s.params.set("noise_threshold", 0.0);  // never converged: every stratum is taken
        s.params.set("min_samples", 2);
        s.params.set("sample_step", 3);
    });
    add("hybrid", "hybrid", [&](StrategySettings& s) {
        s.aamap = ones;
        s.params.set("noise_threshold", 0.0);
        s.params.set("sample_step", 3);
    });
    add("shape-id", "shape-id", [&](StrategySettings& s) { s.params.set("min_samples", k * k); });
    return all;
}

// Supersample: f x f sub-pixels of n x n strata, a (f n) x (f n) grid over the pixel (box filter:
// the mean of the sub-pixels).
std::vector<StratifyingStrategy> supersampleStrategies() {
    std::vector<StratifyingStrategy> all;
    for (int f = 1; f <= 3; ++f)
        for (int n = 1; f * n <= 8; ++n) {
            StrategySettings s;
            s.name = "supersample";
            s.strata = n;
            s.params.set("supersample", f);
            s.params.set("filter", "box");
            all.push_back({fmt::format("supersample f={} n={}", f, n), s, f * n});
        }
    return all;
}

void expectOneRayPerCell(const StratifyingStrategy& s) {
    const int g = s.grid;
    const Tracer tracer(cellProbeScene(g));
    TraceSettings settings;
    settings.width = settings.height = g;
    settings.seed = 11;
    const TraceResult r = tracer.render(frontView(), settings, s.settings);
    const double expected = 1.0 / (static_cast<double>(g) * g);
    for (int y = 0; y < g; ++y)
        for (int x = 0; x < g; ++x) {
            // Sums of ones and zeros divided once: exact up to the float of the mean.
            EXPECT_NEAR(r.image.at(x, y).x, expected, 1e-6)
                << s.name << ", " << g << " x " << g << " grid: cell (" << x << ", " << y << ") got "
                << r.image.at(x, y).x * g * g << " rays instead of 1";
        }
}

TEST(FilmSampling, EveryStratifyingStrategyPutsOneRayInEachCellForKUpTo8) {
    for (int k = 1; k <= 8; ++k) {
        const ImageGrey ones(k, k, 1.0f);
        for (const StratifyingStrategy& s : stratifyingStrategies(k, &ones)) expectOneRayPerCell(s);
    }
}

TEST(FilmSampling, SupersampleSubPixelsTileThePixelOneRayPerCell) {
    for (const StratifyingStrategy& s : supersampleStrategies()) expectOneRayPerCell(s);
}

// With a pixel filter applied by importance sampling the k x k rays of a pixel land one in each
// of k x k cells of equal filter weight: cell (i, j) spans the offsets [F^-1(i/k), F^-1((i+1)/k)] x [F^-1(j/k), F^-1((j+1)/k)]
// from the pixel centre, beyond the pixel itself. One-pixel renders with one cell lit at a time
// (in a probe image of many pixels each pixel's rays would also reach its neighbours' cells).
TEST(FilmSampling, PixelFiltersPutOneRayInEachCellOfEqualFilterWeight) {
    const ImageGrey one(1, 1, 1.0f);
    constexpr PixelFilterMode kDrawn = PixelFilterMode::Importance;
    for (const PixelFilterSettings& fs : {PixelFilterSettings{PixelFilterType::Tent, 0.0f, 0.5f, kDrawn},
                                          PixelFilterSettings{PixelFilterType::Gaussian, 0.0f, 0.5f, kDrawn},
                                          PixelFilterSettings{PixelFilterType::Box, 1.0f, 0.5f, kDrawn}}) {
        const PixelFilter filter(fs);
        const auto edge = [&](int i, int k) {
            return static_cast<double>(0.5f + filter.offset(static_cast<float>(i) / static_cast<float>(k)));
        };
        for (int k : {2, 3}) {
            TraceSettings settings;
            settings.width = settings.height = 1;
            settings.seed = 11;
            settings.filter = fs;
            for (int j = 0; j < k; ++j)
                for (int i = 0; i < k; ++i) {
                    testing::SceneBuilder b;
                    addFilmRectangle(b, edge(i, k), edge(j, k), edge(i + 1, k), edge(j + 1, k));
                    const Tracer tracer(b.scene());
                    for (const StratifyingStrategy& s : stratifyingStrategies(k, &one)) {
                        const TraceResult r = tracer.render(frontView(), settings, s.settings);
                        EXPECT_NEAR(r.image.at(0, 0).x, 1.0 / (k * k), 1e-6)
                            << toString(fs.type) << " r=" << filter.radius() << ", " << s.name << ", k = " << k
                            << ": cell (" << i << ", " << j << ") got " << r.image.at(0, 0).x * k * k << " rays";
                    }
                }
        }
    }
}

// Convolution mode renders exactly the box-pixel image of the same seed, then convolves it: the
// render equals PixelFilter::convolve of the default render, for strategies with one and with
// many rays per pixel. The emitter's edges cut pixels, so the box image is not constant.
TEST(FilmSampling, ConvolutionModeIsTheBoxRenderConvolved) {
    testing::SceneBuilder b;
    addFilmRectangle(b, 0.23, 0.31, 0.71, 0.58);
    const Tracer tracer(b.scene());
    const ImageGrey ones(12, 10, 1.0f);
    TraceSettings box;
    box.width = 12;
    box.height = 10;
    box.seed = 5;
    TraceSettings convolved = box;
    convolved.filter = {PixelFilterType::Gaussian, 0.0f, 0.5f, PixelFilterMode::Convolution};
    const PixelFilter filter(convolved.filter);
    for (const StratifyingStrategy& s : stratifyingStrategies(3, &ones)) {
        const TraceResult plain = tracer.render(frontView(), box, s.settings);
        const TraceResult filtered = tracer.render(frontView(), convolved, s.settings);
        EXPECT_EQ(filtered.image, filter.convolve(plain.image)) << s.name;
        EXPECT_EQ(filtered.primaryRays, plain.primaryRays) << s.name;
        EXPECT_NE(filtered.image, plain.image) << s.name;
    }
}

// A one-pixel image, uniform k x k strata.
TraceResult onePixelUniform(const Tracer& tracer, int k) {
    TraceSettings settings;
    settings.width = settings.height = 1;
    StrategySettings uniform;
    uniform.strata = k;
    return tracer.render(frontView(), settings, uniform);
}

// A white quad over exactly the top-left quadrant of a one-pixel image: with k even, (k/2)^2 of
// the k^2 strata lie inside it, so the coverage is exactly 1/4 (no sampling noise at all).
TEST(FilmSampling, QuadOverOneQuadrantCoversExactlyAQuarterForEvenK) {
    for (const auto& [u0, v0] : std::vector<std::pair<double, double>>{{0.0, 0.0}, {0.5, 0.0}, {0.0, 0.5}, {0.5, 0.5}}) {
        testing::SceneBuilder b;
        addFilmRectangle(b, u0, v0, u0 + 0.5, v0 + 0.5);
        const Tracer tracer(b.scene());
        for (int k : {2, 4, 6}) {
            const TraceResult r = onePixelUniform(tracer, k);
            EXPECT_EQ(r.image.at(0, 0), glm::vec3(0.25f)) << "k = " << k << ", quadrant at (" << u0 << ", " << v0 << ")";
            EXPECT_EQ(r.primaryRays.at(0, 0), k * k);
        }
    }
}

// Non-finite samples are dropped and the pixel is the mean of the finite ones: the top half of
// the pixel shows a lit surface whose albedo is NaN, the bottom half an emitter of radiance 1, so
// the pixel reads exactly 1 and half its k^2 samples are counted as non-finite.
TEST(FilmSampling, NonFiniteStrataAreLeftOutOfThePixelMean) {
    testing::SceneBuilder b;
    addFilmRectangle(b, 0.0, 0.5, 1.0, 1.0);
    const auto broken = b.material("broken", glm::vec3(std::numeric_limits<float>::quiet_NaN()));
    const PinholeCamera camera = PinholeCamera::fromView(frontView());
    const glm::vec3 topLeft = camera.direction(0.0f, 0.0f), middleRight = camera.direction(1.0f, 0.5f);
    b.quad(glm::vec3(topLeft.x, middleRight.y, -1.0f), glm::vec3(middleRight.x - topLeft.x, 0, 0),
           glm::vec3(0, topLeft.y - middleRight.y, 0), broken);
    b.pointLight({0, 0.5f, -0.5f}, glm::vec3(1.0f));
    const Tracer tracer(b.scene());
    for (int k : {2, 4, 6}) {
        const TraceResult r = onePixelUniform(tracer, k);
        EXPECT_EQ(r.nonFiniteSamples, static_cast<std::uint64_t>(k * k / 2)) << "k = " << k;
        EXPECT_EQ(r.image.at(0, 0), glm::vec3(1.0f)) << "k = " << k;
    }
}

}  // namespace
}  // namespace aamap
