#pragma once
// How well an aamap predicts where aliasing is (DESIGN.md section 6; the measure the paper
// lacked).
//
//   true aliasing T = pixels where FLIP(1-ray image vs converged reference) > aliasingThreshold
//   flagged       F = pixels where aamap > 0
//   recall          = |F and T| / |T|   (1 when T is empty: there was nothing to find)
//   precision       = |F and T| / |F|   (1 when F is empty: nothing flagged, nothing wrong)
//   flagged fraction = |F| / pixel count
//
// The empty-denominator conventions keep both ratios in [0,1] and make the degenerate cases
// read as "no misses" and "no false alarms" respectively; the raw counts are reported as well so
// that a table can show them instead.
#include <cstddef>

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
};

// From a precomputed FLIP error map (1-ray vs reference) and the aamap, same size.
// Throws std::invalid_argument on a size mismatch or empty input.
MapQuality mapQuality(const ImageGrey& flipError, const ImageGrey& aamap, float aliasingThreshold = kDefaultFlipThreshold);

// From the images: computes the FLIP map of oneRay against reference, then the counts above.
MapQuality mapQuality(const ImageRGB& oneRay, const ImageRGB& reference, const ImageGrey& aamap,
                      const MapQualityOptions& options = {});

}  // namespace aamap::metrics
