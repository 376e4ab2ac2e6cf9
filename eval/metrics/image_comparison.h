#pragma once
// Every figure aamap reports for one image against a reference, computed in one place: the
// experiment's per-render metrics and `aamap diff` both call it, so the two always agree.
#include <optional>

#include "core/image.h"
#include "eval/metrics/flip.h"
#include "eval/metrics/pixel_error.h"

namespace aamap::metrics {

struct ComparisonOptions {
    float exposure = 1.0f;                           // display transform of both images
    float ppd = kDefaultPpd;                         // FLIP's viewing condition
    float flipThreshold = kDefaultFlipThreshold;     // FLIP above it: a pixel in error
    double mseThreshold = kDefaultErrorThreshold;    // display-space squared error: a pixel in error
    bool flip = true;                                // LDR-FLIP of what the PNGs show
    bool flipHdr = false;                            // HDR-FLIP of the linear radiance
};

struct Comparison {
    PixelError display;              // MSE family in display space (pixel_error.h)
    std::optional<FlipResult> flip;  // LDR-FLIP, with its error map
    std::optional<FlipResult> flipHdr;
};

// Throws std::invalid_argument when the sizes differ or the images are empty.
Comparison compareImages(const ImageRGB& reference, const ImageRGB& test, const ComparisonOptions& options);

}  // namespace aamap::metrics
