#pragma once
// FLIP's colour spaces and colour pipeline (HPG 2020, section 4.1).
//
// Linear sRGB (D65) -> CIE XYZ -> YCxCz, the linearised L*a*b* of Zhang and Wandell in which the
// contrast sensitivity filters are applied; after filtering: back to linear RGB, clamped to
// [0,1] (the filtered colour must be displayable), then CIE L*a*b*, the Hunt adjustment (chroma
// scaled by 0.01 L), the HyAB distance |dL| + ||(da, db)||, raised to qc and redistributed to
// [0,1] so that the knee pc * cmax maps to pt.
#include <glm/vec3.hpp>

#include "core/image.h"
#include "eval/metrics/flip_filters.h"

namespace aamap::metrics::flip {

float srgbToLinear(float c);  // sRGB EOTF on [0,1]
glm::vec3 linearRgbToXyz(glm::vec3 rgb);
glm::vec3 xyzToLinearRgb(glm::vec3 xyz);
glm::vec3 xyzToYcxcz(glm::vec3 xyz);
glm::vec3 ycxczToXyz(glm::vec3 ycc);
glm::vec3 xyzToLab(glm::vec3 xyz);

inline glm::vec3 linearRgbToYcxcz(glm::vec3 rgb) { return xyzToYcxcz(linearRgbToXyz(rgb)); }

// Hunt-adjusted L*a*b*: a and b scaled by 0.01 L (dark colours look less chromatic).
inline glm::vec3 hunt(glm::vec3 lab) { return {lab.x, 0.01f * lab.x * lab.y, 0.01f * lab.x * lab.z}; }

// HyAB: city-block on lightness, Euclidean on chroma. Symmetric in its arguments bit for bit.
float hyab(glm::vec3 a, glm::vec3 b);

// cmax: the HyAB distance between Hunt-adjusted green and blue, raised to qc (the largest
// difference between two colours of the RGB cube).
float maxColourDistance();

// Maps a qc-powered HyAB distance to [0,1]: [0, pc cmax] -> [0, pt], [pc cmax, cmax] -> [pt, 1].
float redistribute(float powered);

// The CSF-filtered version of a YCxCz image (separable, clamp-to-edge borders), TBB over rows.
ImageRGB spatialFilter(const ImageRGB& ycxcz, const SpatialFilters& filters);

// Per-pixel colour difference Delta E_c in [0,1] of two YCxCz images of the same size.
ImageGrey colourDifference(const ImageRGB& refYcxcz, const ImageRGB& testYcxcz, const SpatialFilters& filters);

}  // namespace aamap::metrics::flip
