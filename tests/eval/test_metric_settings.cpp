// The metric settings change the figures as they are defined (docs/experiments.md, "Metrics"):
// metrics.flip_threshold is the FLIP error above which a pixel counts in pct_error_flip (and in
// map quality's true aliasing), metrics.mse_threshold the display-space squared error from which
// a pixel counts in pct_error_mse, metrics.ppd FLIP's viewing distance. Analytic images, figures
// through evaluateRender / evaluateMap, the functions the runner reports.
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "core/image_io.h"
#include "eval/config.h"
#include "eval/evaluate.h"
#include "eval/metrics/flip.h"
#include "eval/metrics/image_comparison.h"
#include "eval/metrics/pixel_error.h"
#include "tests/common/temp_dir.h"

namespace aamap {
namespace {

using Json = nlohmann::ordered_json;

Json figures(const ImageRGB& reference, const ImageRGB& test, const MetricsConfig& m) {
    test::TempDir dir;
    std::vector<std::string> outputs;
    return evaluateRender(reference, test, m, 1.0f, dir.path(), "probe", outputs);
}

// Grey against a ramp of growing contrast, alternating in sign: FLIP errors spread over [0, 1].
struct Ramp {
    ImageRGB reference{64, 16, glm::vec3(0.5f)}, test{64, 16};
    Ramp() {
        for (int y = 0; y < 16; ++y)
            for (int x = 0; x < 64; ++x) {
                const float d = 0.5f * static_cast<float>(x) / 63.0f;
                test.at(x, y) = glm::vec3((x + y) % 2 ? 0.5f + d : 0.5f - d);
            }
    }
};

double percentAbove(const ImageGrey& error, float threshold) {
    std::size_t above = 0;
    for (float e : error.pixels()) above += e > threshold;
    return 100.0 * static_cast<double>(above) / static_cast<double>(error.pixels().size());
}

TEST(MetricSettings, FlipThresholdIsWherePctErrorFlipCounts) {
    const Ramp ramp;
    metrics::ComparisonOptions o;
    o.ppd = static_cast<float>(MetricsConfig{}.ppd);
    const metrics::FlipResult flip = *metrics::compareImages(ramp.reference, ramp.test, o).flip;
    std::vector<double> seen;
    for (double t : {0.02, 0.1, 0.25, 0.5, 0.8}) {
        MetricsConfig m;
        m.flipThreshold = t;
        const Json j = figures(ramp.reference, ramp.test, m);
        EXPECT_DOUBLE_EQ(j["pct_error_flip"].get<double>(), percentAbove(flip.errorMap, static_cast<float>(t))) << t;
        EXPECT_DOUBLE_EQ(j["flip_mean"].get<double>(), flip.mean) << "the threshold only counts";
        seen.push_back(j["pct_error_flip"].get<double>());
    }
    for (std::size_t i = 1; i < seen.size(); ++i) EXPECT_GT(seen[i - 1], seen[i]) << "the ramp spans the thresholds";
}

TEST(MetricSettings, FlipThresholdIsTheTrueAliasingOfMapQuality) {
    const Ramp ramp;
    const ImageGrey aamap(64, 16, 1.0f);
    metrics::FlipOptions o;
    o.ppd = static_cast<float>(MetricsConfig{}.ppd);
    const metrics::FlipResult flip = metrics::flipDisplay(ramp.reference, ramp.test, 1.0f, o);
    for (double t : {0.05, 0.3, 0.6}) {
        MetricsConfig m;
        m.flipThreshold = t;
        test::TempDir dir;
        const Json q = evaluateMap(ramp.test, ramp.reference, aamap, m, 1.0f, dir.path());
        EXPECT_FLOAT_EQ(q["threshold"].get<float>(), static_cast<float>(t));
        EXPECT_DOUBLE_EQ(q["true_fraction"].get<double>(), percentAbove(flip.errorMap, static_cast<float>(t)) / 100.0) << t;
    }
}

// Black reference; a quarter of the test white (display error 1), a quarter the linear value whose
// sRGB code is exactly 0.5 (display error 0.25), half black (0): pct_error_mse is the share of
// pixels whose squared display error is at least the threshold.
TEST(MetricSettings, MseThresholdIsWherePctErrorMseCounts) {
    const float half = std::pow((0.5f + 0.055f) / 1.055f, 2.4f);  // sRGB decode of 0.5
    ImageRGB reference(8, 8, glm::vec3(0.0f)), test(8, 8, glm::vec3(0.0f));
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x) test.at(x, y) = glm::vec3(y < 2 ? 1.0f : y < 4 ? half : 0.0f);
    const struct {
        double threshold, percent;
    } cases[] = {{0.99, 25.0}, {0.5, 25.0}, {0.26, 25.0}, {0.24, 50.0}, {0.01, 50.0}, {1e-9, 50.0}};
    for (const auto& c : cases) {
        MetricsConfig m;
        m.flip = false;
        m.mseThreshold = c.threshold;
        const Json j = figures(reference, test, m);
        EXPECT_DOUBLE_EQ(j["pct_error_mse"].get<double>(), c.percent) << "threshold " << c.threshold;
        EXPECT_NEAR(j["mse"].get<double>(), (16 * 1.0 + 16 * 0.25) / 64.0, 1e-6) << "the threshold only counts";
    }
}

// "At least the threshold": a pixel whose error equals it counts. A grey pixel of display value c
// against black has the error c^2 exactly (the mean of three equal squares of a float).
TEST(MetricSettings, APixelExactlyAtTheMseThresholdCounts) {
    ImageRGB reference(4, 1, glm::vec3(0.0f)), test(4, 1, glm::vec3(0.0f));
    test.at(0, 0) = glm::vec3(0.3f);
    const double c = displayEncode(0.3f);
    MetricsConfig m;
    m.flip = false;
    m.mseThreshold = c * c;
    EXPECT_DOUBLE_EQ(figures(reference, test, m)["pct_error_mse"].get<double>(), 25.0);
    m.mseThreshold = std::nextafter(c * c, 1.0);
    EXPECT_DOUBLE_EQ(figures(reference, test, m)["pct_error_mse"].get<double>(), 0.0);
}

// A one-pixel checkerboard against its mean grey: evaluateRender gives FLIP the configured ppd,
// and the viewing distance matters: up close (few pixels per degree) the pattern is plain to see,
// from the default distance it has nearly blurred into the grey.
TEST(MetricSettings, PpdIsFlipsViewingDistance) {
    ImageRGB reference(32, 32, glm::vec3(0.5f)), test(32, 32);
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 32; ++x) test.at(x, y) = glm::vec3((x + y) % 2 ? 1.0f : 0.0f);
    std::vector<double> means;
    for (double ppd : {5.0, 20.0, 67.0206, 200.0}) {
        MetricsConfig m;
        m.ppd = ppd;
        const Json j = figures(reference, test, m);
        metrics::ComparisonOptions o;
        o.ppd = static_cast<float>(ppd);
        EXPECT_DOUBLE_EQ(j["flip_mean"].get<double>(), metrics::compareImages(reference, test, o).flip->mean) << ppd;
        means.push_back(j["flip_mean"].get<double>());
    }
    EXPECT_GT(means[0], 0.5) << "5 ppd: the checkerboard is obvious";
    EXPECT_GT(means[0], means[1]);
    EXPECT_GT(means[1], means[2]);
    EXPECT_LT(means[2], 0.1) << "67 ppd: the checkerboard is nearly grey";
    EXPECT_NE(means[3], means[2]);
}

// The oracle map's fixed point on images where the answer is known: a 1-ray image equal to the
// reference needs nothing; one with a wrong block needs at least that block, and the image that
// takes the reference there has no error left.
TEST(OracleMap, FlagsWhatTheReferenceSaysAndReachesAFixedPoint) {
    const MetricsConfig m;
    const ImageRGB reference(32, 24, glm::vec3(0.3f));
    const OracleMap none = oracleMap(reference, reference, m, 1.0f);
    EXPECT_EQ(none.rounds, 1);
    EXPECT_EQ(none.residualErrorPercent, 0.0);
    for (float v : none.map.pixels()) EXPECT_EQ(v, 0.0f);

    ImageRGB oneRay = reference;
    for (int y = 10; y < 13; ++y)
        for (int x = 14; x < 17; ++x) oneRay.at(x, y) = glm::vec3(0.9f);  // a wrong 3x3 block
    const OracleMap o = oracleMap(oneRay, reference, m, 1.0f);
    for (int y = 10; y < 13; ++y)
        for (int x = 14; x < 17; ++x) EXPECT_EQ(o.map.at(x, y), 1.0f) << x << "," << y;
    EXPECT_EQ(o.map.at(0, 0), 0.0f);
    EXPECT_GE(o.rounds, 2);  // the last round finds nothing new
    EXPECT_EQ(o.residualErrorPercent, 0.0);
    // The fixed point: the composite on the map is within the threshold everywhere.
    ImageRGB composite = oneRay;
    for (std::size_t i = 0; i < composite.size(); ++i)
        if (o.map.pixels()[i] > 0) composite.pixels()[i] = reference.pixels()[i];
    EXPECT_EQ(metrics::flipDisplay(reference, composite, 1.0f, {}).fractionAbove, 0.0);
}

}  // namespace
}  // namespace aamap
