#pragma once
// Pixel-level error metrics: MSE, RMSE, PSNR and the share of pixels "in error by MSE" (the
// statistic of the paper's Table 3), in two clearly separated spaces:
//
//  * ErrorSpace::Display: what the PNGs show. Each channel is multiplied by the exposure, clamped
//    to [0,1] and sRGB-encoded, exactly like core's toneMap() but without the 8-bit rounding, so the
//    values are the display code values divided by 255. PSNR peak = 1.0 (full-scale white).
//  * ErrorSpace::Linear: the raw linear radiance (no exposure, no clamp). PSNR peak = 1.0 as well,
//    i.e. the radiance that the PNGs display as white at exposure 1; pass a different peak (e.g. the
//    reference maximum) in PixelErrorOptions when that convention does not suit.
//
// In both spaces non-finite channel values count as 0, as toneMap() shows them black.
// Sums are accumulated in double per row and added in row order, so results do not depend on
// the number of threads.
#include <cstddef>

#include "core/image.h"

namespace aamap::metrics {

enum class ErrorSpace { Display, Linear };

// Default threshold of "pixel in error": the per-pixel squared error, averaged over R, G, B, is at
// least (2/255)^2 ~ 6.15e-5, i.e. the RMS channel difference is >= 2 8-bit code values. Why 2:
// two renders of the same radiance can already differ by 1 code value after rounding to 8 bits
// (the PNGs are quantised), while a continuous difference of >= 2/255 always survives
// quantisation as >= 2 code values, which is around the just-noticeable step of 8-bit sRGB in
// mid-tones. The threshold is in the units of the chosen space: it is meant for Display; in
// Linear it is much harsher in highlights and more lenient in shadows.
inline constexpr double kDefaultErrorThreshold = (2.0 / 255.0) * (2.0 / 255.0);

struct PixelErrorOptions {
    ErrorSpace space = ErrorSpace::Display;
    float exposure = 1.0f;                          // Display only, as in toneMap()
    double peak = 1.0;                              // PSNR peak signal in the chosen space
    double errorThreshold = kDefaultErrorThreshold;  // per-pixel mean-over-channels squared error
};

struct PixelError {
    double mse = 0.0;   // mean over pixels and channels of the squared difference
    double rmse = 0.0;  // sqrt(mse)
    double psnr = 0.0;  // 10 log10(peak^2 / mse); +infinity when mse == 0 (identical images)
    std::size_t pixelsInError = 0;  // per-pixel mean squared error >= errorThreshold
    double fractionInError = 0.0;   // pixelsInError / pixel count, in [0,1] (x100 for the paper's %)
};

// Throws std::invalid_argument when the sizes differ or the images are empty.
PixelError pixelError(const ImageRGB& reference, const ImageRGB& test, const PixelErrorOptions& options = {});

// Named shorthands for the two spaces, with the default threshold and peak 1.
PixelError pixelErrorDisplay(const ImageRGB& reference, const ImageRGB& test, float exposure = 1.0f);
PixelError pixelErrorLinear(const ImageRGB& reference, const ImageRGB& test);

// Per-pixel squared error averaged over the three channels (the map behind mse and
// fractionInError), in the space of the options.
ImageGrey squaredErrorMap(const ImageRGB& reference, const ImageRGB& test, const PixelErrorOptions& options = {});

// 10 log10(peak^2 / mse); +infinity for mse == 0. (JSON writers emit +inf as null.)
double psnrFromMse(double mse, double peak = 1.0);

}  // namespace aamap::metrics
