#pragma once
// FLIP (Andersson et al., "FLIP: A Difference Evaluator for Alternating Images", HPG 2020) and
// HDR-FLIP (Andersson et al., "Visualizing Errors in Rendered High Dynamic Range Images",
// Eurographics 2021), implemented from the papers; constants, filter radii and the order of
// operations follow the reference implementation (NVlabs/flip, package flip-evaluator 1.7),
// against which tests/metrics cross-checks the mean error.
//
// LDR-FLIP: colour pipeline (flip_color.h) and feature pipeline (flip_feature.h), combined per
// pixel as Delta E = Delta E_c ^ (1 - Delta E_f) in [0,1].
// HDR-FLIP: the images are exposed at numExposures evenly spaced stops in [start, stop], tone
// mapped (ACES by default), clamped, and compared with LDR-FLIP; the per-pixel max is kept.
// The default range comes from the *reference*: start makes its brightest pixel reach 85% of
// the tone mapper's output, stop does the same for its median luminance.
//
// LDR-FLIP is symmetric (swapping reference and test gives the same map, bit for bit: every
// step depends on |r - t| or (r - t)^2). HDR-FLIP is not in general, since its exposure range is
// taken from the reference.
#include <optional>

#include <glm/vec3.hpp>

#include "core/image.h"

namespace aamap::metrics {

// Pixels per degree of visual angle for a viewer at distance d looking at a display of the
// given width (pixels and metres): d * (pixels / width) * pi / 180.
constexpr float pixelsPerDegree(float distanceMetres, float displayWidthPixels, float displayWidthMetres) {
    return distanceMetres * (displayWidthPixels / displayWidthMetres) * (3.14159265358979f / 180.0f);
}
// 0.7 m from a 0.7 m wide 3840-pixel monitor: ~67.02 PPD (FLIP's default).
inline constexpr float kDefaultPpd = pixelsPerDegree(0.7f, 3840.0f, 0.7f);
inline constexpr float kDefaultFlipThreshold = 0.1f;

enum class ToneMapper { Aces, Hable, Reinhard };

struct FlipOptions {
    float ppd = kDefaultPpd;
    float threshold = kDefaultFlipThreshold;  // fractionAbove counts error > threshold
    // HDR-FLIP only.
    ToneMapper toneMapper = ToneMapper::Aces;
    std::optional<float> startExposure;  // stops (log2 of the scale); default from the reference
    std::optional<float> stopExposure;
    int numExposures = 0;  // 0: max(2, ceil(stop - start))
};

struct FlipResult {
    ImageGrey errorMap;         // per-pixel FLIP in [0,1]
    double mean = 0.0;          // mean of errorMap
    double fractionAbove = 0.0; // share of pixels with error > threshold, in [0,1]
    // HDR-FLIP only (zero / empty for LDR-FLIP).
    float startExposure = 0.0f;
    float stopExposure = 0.0f;
    int numExposures = 0;
    ImageGrey exposureMap;  // which exposure gave the max: index / (numExposures - 1), in [0,1]
};

// LDR-FLIP of linear RGB images meant to lie in [0,1] (values are clamped to [0,1] first, as the
// reference does). Throws std::invalid_argument when sizes differ or images are empty.
FlipResult flipLdr(const ImageRGB& reference, const ImageRGB& test, const FlipOptions& options = {});

// LDR-FLIP of sRGB-encoded images in [0,1] (e.g. 8-bit PNG values / 255): decoded, then flipLdr.
FlipResult flipLdrSrgb(const ImageRGB& referenceSrgb, const ImageRGB& testSrgb, const FlipOptions& options = {});

// LDR-FLIP of what the PNGs show: radiance * exposure, non-finite -> 0, clamped to [0,1]
// (without the 8-bit rounding), then flipLdr.
FlipResult flipDisplay(const ImageRGB& reference, const ImageRGB& test, float exposure = 1.0f,
                       const FlipOptions& options = {});

// HDR-FLIP of linear radiance (negative and non-finite values read as 0).
FlipResult flipHdr(const ImageRGB& reference, const ImageRGB& test, const FlipOptions& options = {});

// Same error map, colour mapped with magma (linear RGB; see magma.h).
ImageRGB flipMagma(const FlipResult& result);

// The tone mappers of HDR-FLIP (ACES filmic fit with FLIP's 0.6 pre-exposure cancelled, Hable,
// Reinhard on luminance). Output is not clamped.
glm::vec3 toneMapHdr(glm::vec3 linear, ToneMapper toneMapper);

struct ExposureRange {
    float start = 0.0f;
    float stop = 0.0f;
};
// HDR-FLIP's automatic range from the reference. When the median luminance is 0, the smallest
// non-zero luminance stands in for it; an all-black reference gives [0, 0].
ExposureRange automaticExposureRange(const ImageRGB& reference, ToneMapper toneMapper);

}  // namespace aamap::metrics
