#pragma once
// Parameters of the aamap filter chain (definition in glsl/shared/aamap_filter.h).
#include "glsl/shared/aamap_filter.h"

namespace aamap {

struct FilterParams {
    float exposure = 1.0f;
    int blurRadius = AAMAP_DEFAULT_BLUR_RADIUS;
    float noiseFloor = static_cast<float>(AAMAP_DEFAULT_NOISE_FLOOR);
    float gain = static_cast<float>(AAMAP_DEFAULT_GAIN);
    float flatRange = static_cast<float>(AAMAP_DEFAULT_FLAT_RANGE);
    bool operator==(const FilterParams&) const = default;
};

}  // namespace aamap
