#pragma once
// Where a render is worst: the k square windows with the largest summed error, chosen greedily and
// never overlapping, so that a report can show the few crops a reader should look at first instead
// of making them hunt across the whole image.
#include <vector>

#include "core/image.h"

namespace aamap::metrics {

struct Region {
    int x = 0, y = 0;   // top-left corner, pixels
    int size = 0;       // side of the square window, pixels
    double meanError = 0.0;  // mean of the error map inside the window
};

// The side used by the report: an eighth of the shorter image side, at least 8 pixels and never
// more than the image itself.
int defaultRegionSize(int width, int height);

// Greedy top-k: the window (size x size, fully inside the image) with the largest sum, then the
// largest among windows that do not overlap any chosen one, and so on. Ties go to the smallest
// (y, x), so the result is deterministic. Stops early when no window with a positive sum is left.
// Sorted by decreasing summed error. Empty for an empty map or size < 1.
std::vector<Region> worstRegions(const ImageGrey& error, int size, int count);

}  // namespace aamap::metrics
