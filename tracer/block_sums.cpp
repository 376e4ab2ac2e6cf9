#include "tracer/block_sums.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace aamap {

BlockSums::BlockSums(const ImageGrey& map) : width_(map.width()), height_(map.height()) {
    const std::size_t size = static_cast<std::size_t>(width_ + 1) * (height_ + 1);
    table_.assign(size, 0.0);
    nonZero_.assign(size, 0);
    for (int y = 0; y < height_; ++y) {
        double row = 0.0;
        std::uint32_t rowCount = 0;
        for (int x = 0; x < width_; ++x) {
            const float a = map.at(x, y);
            const double v = std::isnan(a) ? 1.0 : static_cast<double>(std::clamp(a, 0.0f, 1.0f));
            row += v;
            rowCount += v > 0.0 ? 1u : 0u;
            table_[index(x + 1, y + 1)] = table_[index(x + 1, y)] + row;
            nonZero_[index(x + 1, y + 1)] = nonZero_[index(x + 1, y)] + rowCount;
        }
    }
}

BlockSums BlockSums::fromTables(int width, int height, std::vector<double> sums, std::vector<std::uint32_t> counts) {
    const std::size_t size = static_cast<std::size_t>(width + 1) * (height + 1);
    if (width < 0 || height < 0 || sums.size() != size || counts.size() != size)
        throw std::invalid_argument("block-sum tables have the wrong size");
    BlockSums b;
    b.width_ = width;
    b.height_ = height;
    b.table_ = std::move(sums);
    b.nonZero_ = std::move(counts);
    return b;
}

double BlockSums::sum(int x0, int y0, int x1, int y1) const {
    x0 = std::max(x0, 0);
    y0 = std::max(y0, 0);
    x1 = std::min(x1, width_ - 1);
    y1 = std::min(y1, height_ - 1);
    if (x0 > x1 || y0 > y1) return 0.0;
    // Unsigned wrap-around cancels exactly in the count.
    const std::uint32_t count = nonZero_[index(x1 + 1, y1 + 1)] - nonZero_[index(x0, y1 + 1)] -
                                nonZero_[index(x1 + 1, y0)] + nonZero_[index(x0, y0)];
    if (count == 0) return 0.0;
    const double s = table_[index(x1 + 1, y1 + 1)] - table_[index(x0, y1 + 1)] - table_[index(x1 + 1, y0)] +
                     table_[index(x0, y0)];
    return std::max(s, 0.0);  // rounding never makes a sum of non-negative values negative
}

}  // namespace aamap
