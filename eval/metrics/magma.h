#pragma once
// The magma colour map (matplotlib, CC0) used by FLIP's error images.
#include <glm/vec3.hpp>

#include "core/image.h"

namespace aamap::metrics {

// Display (sRGB-encoded) magma colour for t in [0,1] (clamped; NaN reads as 0), interpolated
// linearly between 52 samples of the 256-entry table.
glm::vec3 magmaSrgb(float t);

// An error map in magma for reports. The result is *linear* RGB, like every ImageRGB, so that
// core's toneMap(image, 1.0f) (sRGB OETF) writes the usual magma PNG.
ImageRGB magmaImage(const ImageGrey& values);

}  // namespace aamap::metrics
