#pragma once
// The paper's adaptive subsampling (section 4): trace a grid of spacing s (plus the last row and
// column, so any size is covered). Each s x s block whose aamap sum (corners included) exceeds t
// is split into four, recursively down to single pixels; the inside of every other block is
// interpolated from its traced corners. Traced pixels get k(p) x k(p) strata ("Space 8/16").
// The decision depends on the map only, so it is planned before any ray is traced.
#include <cstdint>
#include <vector>

#include "core/image.h"
#include "tracer/block_sums.h"

namespace aamap {

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

SubsamplePlan planSubsampling(const BlockSums& sums, int spacing, double threshold);

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
