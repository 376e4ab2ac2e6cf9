#pragma once
// Image comparisons for the CPU-versus-GPU tests.
#include <cmath>
#include <cstddef>

#include <gtest/gtest.h>

#include "core/image.h"

namespace aamap::test {

// The largest |a - b| over the pixels (a NaN on either side makes it NaN, so no tolerance holds);
// a size mismatch fails the test and returns infinity.
inline float maxAbsDiff(const ImageGrey& a, const ImageGrey& b) {
    EXPECT_EQ(a.width(), b.width());
    EXPECT_EQ(a.height(), b.height());
    if (a.size() != b.size()) return INFINITY;
    float worst = 0.0f;
    for (std::size_t i = 0; i < a.size(); ++i) {
        const float d = std::fabs(a.data()[i] - b.data()[i]);
        if (!(d <= worst)) worst = d;  // NaN sticks
    }
    return worst;
}

}  // namespace aamap::test
