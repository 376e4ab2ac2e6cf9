#pragma once
// O(1) sums of aamap values over rectangles: a summed-area table with double accumulation (float
// would lose the small values of a 512x512 map next to a large running total). Tracer-independent.
//
// A second, integer table counts the non-zero values, so that a block of exact zeros sums to exactly
// 0 whatever the rounding of the double table (the paper's threshold t = 0 relies on it).
//
// GPU counterpart (to be added as a render-graph reduction pass): two tables of
// (width + 1) x (height + 1) with S(0, y) = S(x, 0) = 0 and, for i <= x, j <= y,
//   S(x + 1, y + 1) = sum of v(i, j), v = clamp(aamap, 0, 1), NaN -> 1 (float-float hi + lo, or
//   a prefix per tile plus tile offsets: block sums must agree with this class to ~1e-6 relative),
//   C(x + 1, y + 1) = count of v(i, j) > 0 (R32_UINT, exact).
// BlockSums::fromTables() takes them as they are read back.
#include <cstdint>
#include <vector>

#include "core/image.h"

namespace aamap {

class BlockSums {
public:
    BlockSums() = default;
    // Values are clamped to [0, 1]; NaN counts as 1 (unsure: the block must be refined).
    explicit BlockSums(const ImageGrey& map);
    // Precomputed (width + 1) x (height + 1) tables laid out as above (row-major).
    static BlockSums fromTables(int width, int height, std::vector<double> sums, std::vector<std::uint32_t> counts);

    int width() const { return width_; }
    int height() const { return height_; }
    // Sum over the inclusive rectangle [x0, x1] x [y0, y1] (clipped to the image; empty -> 0).
    double sum(int x0, int y0, int x1, int y1) const;

private:
    std::size_t index(int x, int y) const { return static_cast<std::size_t>(y) * (width_ + 1) + x; }
    int width_ = 0, height_ = 0;
    std::vector<double> table_;
    std::vector<std::uint32_t> nonZero_;
};

}  // namespace aamap
