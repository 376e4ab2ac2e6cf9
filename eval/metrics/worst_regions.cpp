#include "eval/metrics/worst_regions.h"

#include <algorithm>
#include <cstdlib>

namespace aamap::metrics {

int defaultRegionSize(int width, int height) {
    const int shorter = std::min(width, height);
    return std::min(shorter, std::max(8, shorter / 8));
}

std::vector<Region> worstRegions(const ImageGrey& error, int size, int count) {
    const int w = error.width(), h = error.height();
    std::vector<Region> chosen;
    if (w <= 0 || h <= 0 || size < 1 || size > w || size > h) return chosen;
    // Summed-area table in double: a window sum is four lookups, whatever its size.
    const int sw = w + 1;
    std::vector<double> sat(static_cast<std::size_t>(sw) * (h + 1), 0.0);
    for (int y = 0; y < h; ++y) {
        double row = 0.0;
        for (int x = 0; x < w; ++x) {
            row += std::max(0.0f, error.at(x, y));
            sat[(y + 1) * sw + x + 1] = sat[y * sw + x + 1] + row;
        }
    }
    const auto sum = [&](int x, int y) {
        return sat[(y + size) * sw + x + size] - sat[y * sw + x + size] - sat[(y + size) * sw + x] + sat[y * sw + x];
    };
    const auto overlapsChosen = [&](int x, int y) {
        return std::any_of(chosen.begin(), chosen.end(), [&](const Region& r) {
            return std::abs(r.x - x) < size && std::abs(r.y - y) < size;
        });
    };
    while (static_cast<int>(chosen.size()) < count) {
        double best = 0.0;
        int bx = -1, by = -1;
        for (int y = 0; y + size <= h; ++y)
            for (int x = 0; x + size <= w; ++x) {
                const double s = sum(x, y);
                if (s > best && !overlapsChosen(x, y)) best = s, bx = x, by = y;
            }
        if (bx < 0) break;
        chosen.push_back({bx, by, size, best / (static_cast<double>(size) * size)});
    }
    return chosen;
}

}  // namespace aamap::metrics
