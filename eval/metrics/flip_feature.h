#pragma once
// FLIP's feature pipeline (HPG 2020, section 4.2): edges and points are detected on the
// achromatic channel, normalised to [0,1] as (Y + 16) / 116, with the first and second
// derivatives of a Gaussian; the feature difference is
//   Delta E_f = ( max(| |grad r| - |grad t| |, | |hess r| - |hess t| |) / sqrt(2) )^qf
// where |grad| = sqrt(dx^2 + dy^2) and |hess| = sqrt(dxx^2 + dyy^2). The final FLIP value is
// Delta E_c ^ (1 - Delta E_f): a changed feature pushes the colour error towards 1.
#include <glm/vec2.hpp>

#include "core/image.h"
#include "eval/metrics/flip_filters.h"

namespace aamap::metrics::flip {

// Per-pixel (edge magnitude, point magnitude) of one YCxCz image.
Image<glm::vec2> featureResponse(const ImageRGB& ycxcz, const FeatureFilter& filter);

// Per-pixel Delta E_f in [0,1] of two YCxCz images of the same size.
ImageGrey featureDifference(const ImageRGB& refYcxcz, const ImageRGB& testYcxcz, const FeatureFilter& filter);

}  // namespace aamap::metrics::flip
