#pragma once
// The paper's adaptive subsampling (section 4), with a gradient refinement beyond the paper. Trace
// a grid of spacing s (plus the last row and column, so any size is covered). Each s x s block
// whose aamap sum (corners included) exceeds t is split into four, recursively down to single
// pixels: that decision depends on the map only, so it is planned before any ray is traced. Then,
// in rounds, every block that would be interpolated traces the points a split adds (its edge
// midpoints and centre) and compares them with the bilinear prediction from its corners, in
// display space: where the prediction is off by more than the gradient tolerance (a steep smooth
// gradient the map does not see: a hot spot, a light's falloff, a soft shadow) its four quarters
// are tested in turn, down to the pixel; otherwise the quarters, whose corners are now all traced,
// are interpolated. Traced pixels get k(p) x k(p) strata ("Space 8/16").
#include <cstdint>
#include <vector>

#include "core/image.h"
#include "tracer/block_sums.h"

namespace aamap {

// The strategy's name and the parameter keys other layers name (the viewer's keys), as its
// declaration (subsampleStrategy(), strategies/subsample.cpp) gives them.
inline constexpr const char* kSubsampleStrategyName = "aamap-subsample";
inline constexpr const char* kSubsampleSpacing = "spacing";
inline constexpr const char* kSubsampleThreshold = "threshold";

// Pixels [x0, x1] x [y0, y1], inclusive; its four corners are traced.
struct Block {
    int x0, y0, x1, y1;
};

struct SubsamplePlan {
    Image<std::uint8_t> traced;       // 1: trace this pixel
    std::vector<Block> interpolated;  // leaf blocks whose untraced pixels are interpolated
};

// Grid positions 0, s, 2s, ... and size - 1.
std::vector<int> gridLines(int size, int spacing);

// Whether the block has a pixel that is not one of its corners (something to interpolate).
bool hasInnerPixels(const Block& block);
// The blocks a split gives: four quarters at the midpoints (x0 + x1) / 2, (y0 + y1) / 2, or two
// halves where one side has no pixel between its corners. Their corners are the block's corners,
// its edge midpoints and its centre. Only for blocks with inner pixels.
std::vector<Block> splitBlock(const Block& block);

SubsamplePlan planSubsampling(const BlockSums& sums, int spacing, double threshold);

// The interpolation error predicted for the block: over the corners that splitBlock(block) adds,
// the largest display-space difference (core's displayEncode) between the traced value there and the bilinear
// prediction from the block's corners, as the RMS over R, G, B (the display MSE metric's per-pixel
// error, square-rooted), in 8-bit code values (1 = 1/255). The image must hold traced values at
// all those points.
float predictedInterpolationError(const ImageRGB& image, const Block& block, float exposure);

// The gradient tolerance's default, in 8-bit display code values: 2, the per-pixel error from
// which the reports count a pixel as an MSE error (squared error >= (2/255)^2, averaged over the
// channels). LDR-FLIP reaches the reports' 0.1 only for a smooth difference of 4 to 8 code values
// (a grey bump, `aamap diff`), so a block predicted to err by less is interpolated without an
// error either count sees.
inline constexpr double kDefaultGradientTolerance = 2.0;
// From this tolerance on no block can be split (a display difference is at most 255 code values):
// the rounds are skipped and no probe is traced.
inline constexpr double kGradientToleranceOff = 255.0;

// Bilinear from the four corners, for the pixels strictly inside the block.
void interpolateBlock(ImageRGB& image, const Block& block);
// Linear along row y (or column x) between consecutive traced pixels of [from, to] (ends traced).
void interpolateRow(ImageRGB& image, const Image<std::uint8_t>& traced, int y, int from, int to);
void interpolateColumn(ImageRGB& image, const Image<std::uint8_t>& traced, int x, int from, int to);
// Completes the image once every traced pixel holds its estimate: the border pixels of each
// interpolated block along the border line between the nearest traced pixels (no cracks where a
// neighbour was refined), then the inner pixels bilinearly.
void fillPlan(ImageRGB& image, const SubsamplePlan& plan);

}  // namespace aamap
