#pragma once
// The two filter banks of FLIP (Andersson et al., HPG 2020), as 1D kernels applied separably.
//
// Colour pipeline: the contrast sensitivity functions of the opponent channels are Gaussians in
// the spatial domain, written as g(x) = a sqrt(pi/b) exp(-pi^2 x^2 / b) with x in degrees of
// visual angle (one pixel = 1/ppd degrees). Y (achromatic) and Cx (red-green) use one Gaussian
// each; Cz (blue-yellow) is a sum of two. A sum of two 2D Gaussians is not separable, but each
// term is, so Cz is filtered with two separable kernels whose results are added (each 1D kernel
// carries the square root of its 2D amplitude so that the outer product restores it).
// Normalisation: every 2D kernel sums to 1 (for Cz, the two terms together).
//
// Feature pipeline: a Gaussian with sigma = 0.5 * w * ppd pixels (w = 0.082 degrees) and its
// first and second derivatives, truncated at 3 sigma; the Gaussian sums to 1 and the positive and
// negative lobes of each derivative sum to +1 and -1.
#include <vector>

namespace aamap::metrics::flip {

// Paper constants (HPG 2020, section 4 and table of CSF parameters).
inline constexpr float kPi = 3.14159265358979f;
inline constexpr float kQc = 0.7f;    // exponent of the colour difference
inline constexpr float kPc = 0.4f;    // share of the max difference mapped below the knee
inline constexpr float kPt = 0.95f;   // error value at the knee
inline constexpr float kW = 0.082f;   // feature size in degrees
inline constexpr float kQf = 0.5f;    // exponent of the feature difference

struct CsfGaussian {
    float a;
    float b;
};
inline constexpr CsfGaussian kCsfY{1.0f, 0.0047f};
inline constexpr CsfGaussian kCsfCx{1.0f, 0.0053f};
inline constexpr CsfGaussian kCsfCz1{34.1f, 0.04f};
inline constexpr CsfGaussian kCsfCz2{13.5f, 0.025f};

// 1D kernels of width 2 * radius + 1, tap i at offset i - radius.
struct SpatialFilters {
    int radius = 0;
    std::vector<float> y, cx, cz1, cz2;
};

struct FeatureFilter {
    int radius = 0;
    float sigma = 0.0f;  // pixels
    std::vector<float> gauss, d1, d2;
};

// 3 sigma of the widest CSF Gaussian (sigma^2 = b / (2 pi^2) degrees^2), in pixels.
int spatialFilterRadius(float ppd);
SpatialFilters makeSpatialFilters(float ppd);
FeatureFilter makeFeatureFilter(float ppd);

// Clamp-to-edge index, the border rule of every FLIP convolution.
inline int clampIndex(int i, int n) { return i < 0 ? 0 : (i >= n ? n - 1 : i); }

}  // namespace aamap::metrics::flip
