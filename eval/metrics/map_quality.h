#pragma once
// How well an aamap predicts where aliasing is (docs/experiments.md, map quality; the measure the paper
// lacked).
//
//   true aliasing T = pixels where FLIP(1-ray image vs converged reference) > aliasingThreshold
//   flagged       F = pixels where aamap > 0
//   recall          = |F and T| / |T|   (1 when T is empty: there was nothing to find)
//   precision       = |F and T| / |F|   (1 when F is empty: nothing flagged, nothing wrong)
//   flagged fraction = |F| / pixel count
//   own recall      = |F and T'| / |T'|, T' = the pixels of T whose own display value differs
//                     (8-bit sRGB at the exposure, any channel) between the 1-ray image and the
//                     reference. FLIP filters spatially, so a high-contrast edge error raises FLIP
//                     one or two pixels beside it where the images agree exactly; no sampling of
//                     those pixels can change them (measured: over half of T on the Cornell box).
//
// The empty-denominator conventions keep both ratios in [0,1] and make the degenerate cases
// read as "no misses" and "no false alarms" respectively; the raw counts are reported as well so
// that a table can show them instead.
#include <cstddef>
#include <cstdint>

#include "core/image.h"
#include "eval/metrics/flip.h"

namespace aamap::metrics {

enum class FlipRange { Display, Hdr };

struct MapQualityOptions {
    float aliasingThreshold = kDefaultFlipThreshold;  // FLIP above this counts as true aliasing
    FlipRange range = FlipRange::Display;  // Display: flipDisplay() at `exposure`; Hdr: flipHdr()
    float exposure = 1.0f;
    FlipOptions flip;  // ppd, HDR settings
};

struct MapQuality {
    std::size_t pixels = 0;
    std::size_t truePixels = 0;      // |T|
    std::size_t flaggedPixels = 0;   // |F|
    std::size_t truePositives = 0;   // |F and T|
    double recall = 1.0;
    double precision = 1.0;
    double flaggedFraction = 0.0;
    double trueFraction = 0.0;       // |T| / pixels
    // Only with an own-difference mask (else equal to the counts above): |T'| and |F and T'|.
    std::size_t ownTruePixels = 0;
    std::size_t ownTruePositives = 0;
    double ownRecall = 1.0;
};

// 1 where the two images' own display values differ (8-bit sRGB of exposure * rgb, any channel).
Image<std::uint8_t> ownDisplayDifference(const ImageRGB& a, const ImageRGB& b, float exposure);

// From a precomputed FLIP error map (1-ray vs reference) and the aamap, same size, and optionally
// the own-difference mask (ownDisplayDifference; without it T' = T).
// Throws std::invalid_argument on a size mismatch or empty input.
MapQuality mapQuality(const ImageGrey& flipError, const ImageGrey& aamap, float aliasingThreshold = kDefaultFlipThreshold,
                      const Image<std::uint8_t>* ownDiffers = nullptr);

// From the images: computes the FLIP map of oneRay against reference, then the counts above.
MapQuality mapQuality(const ImageRGB& oneRay, const ImageRGB& reference, const ImageGrey& aamap,
                      const MapQualityOptions& options = {});

}  // namespace aamap::metrics
