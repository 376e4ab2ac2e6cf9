#include "eval/metrics/flip.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>
#include <glm/common.hpp>
#include <tbb/parallel_for.h>

#include "eval/metrics/flip_color.h"
#include "eval/metrics/flip_feature.h"
#include "eval/metrics/flip_filters.h"
#include "eval/metrics/magma.h"

namespace aamap::metrics {
namespace {

void checkInputs(const ImageRGB& a, const ImageRGB& b, const FlipOptions& o) {
    if (a.empty() || b.empty()) throw std::invalid_argument("FLIP: empty image");
    if (a.width() != b.width() || a.height() != b.height())
        throw std::invalid_argument(
            fmt::format("FLIP: sizes differ ({}x{} vs {}x{})", a.width(), a.height(), b.width(), b.height()));
    if (!(o.ppd > 0.0f)) throw std::invalid_argument("FLIP: pixels per degree must be positive");
}

// Applies f to every pixel of an image (TBB over rows).
template <class F>
ImageRGB mapPixels(const ImageRGB& in, F f) {
    ImageRGB out(in.width(), in.height());
    tbb::parallel_for(0, in.height(), [&](int y) {
        for (int x = 0; x < in.width(); ++x) out.at(x, y) = f(in.at(x, y));
    });
    return out;
}

glm::vec3 finiteOrZero(glm::vec3 c) {
    for (int k = 0; k < 3; ++k)
        if (!std::isfinite(c[k])) c[k] = 0.0f;
    return c;
}

// The LDR-FLIP map of two linear RGB images already in [0,1].
ImageGrey ldrFlipMap(const ImageRGB& reference, const ImageRGB& test, float ppd) {
    const ImageRGB refYcc = mapPixels(reference, flip::linearRgbToYcxcz);
    const ImageRGB testYcc = mapPixels(test, flip::linearRgbToYcxcz);
    ImageGrey colour = flip::colourDifference(refYcc, testYcc, flip::makeSpatialFilters(ppd));
    const ImageGrey feature = flip::featureDifference(refYcc, testYcc, flip::makeFeatureFilter(ppd));
    for (std::size_t i = 0; i < colour.size(); ++i)
        colour.pixels()[i] = std::pow(colour.pixels()[i], 1.0f - feature.pixels()[i]);
    return colour;
}

// Mean and share above threshold; per-row sums added in row order (thread-count independent).
void summarise(FlipResult& r, float threshold) {
    const ImageGrey& m = r.errorMap;
    std::vector<double> rowSum(m.height(), 0.0);
    std::vector<std::size_t> rowAbove(m.height(), 0);
    tbb::parallel_for(0, m.height(), [&](int y) {
        for (int x = 0; x < m.width(); ++x) {
            rowSum[y] += m.at(x, y);
            rowAbove[y] += m.at(x, y) > threshold ? 1 : 0;
        }
    });
    double sum = 0.0;
    std::size_t above = 0;
    for (int y = 0; y < m.height(); ++y) {
        sum += rowSum[y];
        above += rowAbove[y];
    }
    r.mean = sum / double(m.size());
    r.fractionAbove = double(above) / double(m.size());
}

// Rational form (c0 x^2 + c1 x + c2) / (c3 x^2 + c4 x + c5) of the tone mappers.
struct Rational {
    float c[6];
};
Rational rationalOf(ToneMapper tm) {
    switch (tm) {
    case ToneMapper::Aces:  // Narkowicz's ACES fit, FLIP cancels its 0.6 pre-exposure
        return {{0.6f * 0.6f * 2.51f, 0.6f * 0.03f, 0.0f, 0.6f * 0.6f * 2.43f, 0.6f * 0.59f, 0.14f}};
    case ToneMapper::Hable:
        return {{0.231683f, 0.013791f, 0.0f, 0.18f, 0.3f, 0.018f}};
    case ToneMapper::Reinhard:
        break;
    }
    return {{0.0f, 1.0f, 0.0f, 0.0f, 1.0f, 1.0f}};  // x / (x + 1), per luminance
}

float luminance(glm::vec3 c) { return 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b; }

}  // namespace

glm::vec3 toneMapHdr(glm::vec3 c, ToneMapper tm) {
    if (tm == ToneMapper::Reinhard) return c * (1.0f / (1.0f + luminance(c)));
    const Rational r = rationalOf(tm);
    const float* k = r.c;
    return (c * c * k[0] + c * k[1] + k[2]) / (c * c * k[3] + c * k[4] + k[5]);
}

ExposureRange automaticExposureRange(const ImageRGB& reference, ToneMapper tm) {
    // xMax: the input that the tone mapper maps to t = 0.85, the larger root of
    // (c0 - t c3) x^2 + (c1 - t c4) x + (c2 - t c5) = 0.
    const Rational r = rationalOf(tm);
    const float* k = r.c;
    const float t = 0.85f;
    const float a = k[0] - t * k[3], b = k[1] - t * k[4], c = k[2] - t * k[5];
    float xMax;
    if (a == 0.0f) {
        xMax = -c / b;
    } else {
        const float d1 = -0.5f * (b / a);
        xMax = d1 + std::sqrt(d1 * d1 - c / a);
    }

    std::vector<float> lum(reference.size());
    float yMax = -std::numeric_limits<float>::infinity();
    float yMinNonZero = std::numeric_limits<float>::infinity();
    for (std::size_t i = 0; i < lum.size(); ++i) {
        lum[i] = luminance(glm::max(finiteOrZero(reference.pixels()[i]), 0.0f));
        yMax = std::max(yMax, lum[i]);
        if (lum[i] > 0.0f) yMinNonZero = std::min(yMinNonZero, lum[i]);
    }
    if (!(yMax > 0.0f)) return {};  // all black: nothing to expose
    const auto mid = lum.begin() + std::ptrdiff_t(lum.size() / 2);
    std::nth_element(lum.begin(), mid, lum.end());
    const float yMedian = *mid > 0.0f ? *mid : yMinNonZero;
    return {std::log2(xMax / yMax), std::log2(xMax / yMedian)};
}

FlipResult flipLdr(const ImageRGB& reference, const ImageRGB& test, const FlipOptions& options) {
    checkInputs(reference, test, options);
    auto clamp01 = [](glm::vec3 c) { return glm::clamp(finiteOrZero(c), 0.0f, 1.0f); };
    FlipResult r;
    r.errorMap = ldrFlipMap(mapPixels(reference, clamp01), mapPixels(test, clamp01), options.ppd);
    summarise(r, options.threshold);
    return r;
}

FlipResult flipLdrSrgb(const ImageRGB& referenceSrgb, const ImageRGB& testSrgb, const FlipOptions& options) {
    auto decode = [](glm::vec3 c) {
        c = glm::clamp(finiteOrZero(c), 0.0f, 1.0f);
        return glm::vec3(flip::srgbToLinear(c.x), flip::srgbToLinear(c.y), flip::srgbToLinear(c.z));
    };
    checkInputs(referenceSrgb, testSrgb, options);
    return flipLdr(mapPixels(referenceSrgb, decode), mapPixels(testSrgb, decode), options);
}

FlipResult flipDisplay(const ImageRGB& reference, const ImageRGB& test, float exposure, const FlipOptions& options) {
    checkInputs(reference, test, options);
    auto expose = [exposure](glm::vec3 c) { return finiteOrZero(c * exposure); };
    return flipLdr(mapPixels(reference, expose), mapPixels(test, expose), options);
}

FlipResult flipHdr(const ImageRGB& reference, const ImageRGB& test, const FlipOptions& options) {
    checkInputs(reference, test, options);
    auto sanitise = [](glm::vec3 c) { return glm::max(finiteOrZero(c), 0.0f); };
    const ImageRGB ref = mapPixels(reference, sanitise);
    const ImageRGB tst = mapPixels(test, sanitise);

    FlipResult r;
    if (!options.startExposure || !options.stopExposure) {
        const ExposureRange range = automaticExposureRange(ref, options.toneMapper);
        r.startExposure = options.startExposure.value_or(range.start);
        r.stopExposure = options.stopExposure.value_or(range.stop);
    } else {
        r.startExposure = *options.startExposure;
        r.stopExposure = *options.stopExposure;
    }
    if (r.startExposure > r.stopExposure)
        throw std::invalid_argument(
            fmt::format("HDR-FLIP: start exposure {} exceeds stop exposure {}", r.startExposure, r.stopExposure));
    r.numExposures = options.numExposures > 0
                         ? options.numExposures
                         : int(std::max(2.0f, std::ceil(r.stopExposure - r.startExposure)));

    r.errorMap = ImageGrey(ref.width(), ref.height(), 0.0f);
    r.exposureMap = ImageGrey(ref.width(), ref.height(), 0.0f);
    const float step = r.numExposures > 1 ? (r.stopExposure - r.startExposure) / float(r.numExposures - 1) : 0.0f;
    for (int i = 0; i < r.numExposures; ++i) {
        const float scale = std::exp2(r.startExposure + float(i) * step);
        auto toLdr = [&](glm::vec3 c) { return glm::clamp(toneMapHdr(c * scale, options.toneMapper), 0.0f, 1.0f); };
        const ImageGrey e = ldrFlipMap(mapPixels(ref, toLdr), mapPixels(tst, toLdr), options.ppd);
        const float level = r.numExposures > 1 ? float(i) / float(r.numExposures - 1) : 0.0f;
        for (std::size_t p = 0; p < e.size(); ++p) {
            if (e.pixels()[p] > r.errorMap.pixels()[p]) {
                r.errorMap.pixels()[p] = e.pixels()[p];
                r.exposureMap.pixels()[p] = level;
            }
        }
    }
    summarise(r, options.threshold);
    return r;
}

ImageRGB flipMagma(const FlipResult& result) { return magmaImage(result.errorMap); }

}  // namespace aamap::metrics
