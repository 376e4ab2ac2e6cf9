#include "eval/metrics/flip_filters.h"

#include <algorithm>
#include <cmath>

namespace aamap::metrics::flip {
namespace {

// The CSF Gaussian at squared distance x2 (degrees^2).
float csf(float x2, CsfGaussian g) { return g.a * std::sqrt(kPi / g.b) * std::exp(-kPi * kPi * x2 / g.b); }

// Its 1D factor for a separable 2D term: the outer product of two gives csf()'s amplitude.
float csfSqrt(float x2, CsfGaussian g) {
    return std::sqrt(g.a * std::sqrt(kPi / g.b)) * std::exp(-kPi * kPi * x2 / g.b);
}

}  // namespace

int spatialFilterRadius(float ppd) {
    const float bMax = std::max({kCsfY.b, kCsfCx.b, kCsfCz1.b, kCsfCz2.b});
    return int(std::ceil(3.0f * std::sqrt(bMax / (2.0f * kPi * kPi)) * ppd));
}

SpatialFilters makeSpatialFilters(float ppd) {
    SpatialFilters f;
    f.radius = spatialFilterRadius(ppd);
    const int width = 2 * f.radius + 1;
    f.y.resize(width);
    f.cx.resize(width);
    f.cz1.resize(width);
    f.cz2.resize(width);
    float sumY = 0.0f, sumCx = 0.0f, sumCz1 = 0.0f, sumCz2 = 0.0f;
    for (int i = 0; i < width; ++i) {
        const float x = float(i - f.radius) / ppd;  // degrees
        const float x2 = x * x;
        sumY += f.y[i] = csf(x2, kCsfY);
        sumCx += f.cx[i] = csf(x2, kCsfCx);
        sumCz1 += f.cz1[i] = csfSqrt(x2, kCsfCz1);
        sumCz2 += f.cz2[i] = csfSqrt(x2, kCsfCz2);
    }
    // The 2D Cz kernel sums to sumCz1^2 + sumCz2^2: one common factor makes it 1.
    const float czNorm = 1.0f / std::sqrt(sumCz1 * sumCz1 + sumCz2 * sumCz2);
    for (int i = 0; i < width; ++i) {
        f.y[i] /= sumY;
        f.cx[i] /= sumCx;
        f.cz1[i] *= czNorm;
        f.cz2[i] *= czNorm;
    }
    return f;
}

FeatureFilter makeFeatureFilter(float ppd) {
    FeatureFilter f;
    f.sigma = 0.5f * kW * ppd;
    f.radius = int(std::ceil(3.0f * f.sigma));
    const int width = 2 * f.radius + 1;
    f.gauss.resize(width);
    f.d1.resize(width);
    f.d2.resize(width);
    float gSum = 0.0f, d1Pos = 0.0f, d1Neg = 0.0f, d2Pos = 0.0f, d2Neg = 0.0f;
    for (int i = 0; i < width; ++i) {
        const float x = float(i - f.radius);
        const float g = std::exp(-(x * x) / (2.0f * f.sigma * f.sigma));
        const float d1 = -x * g;                                    // shape of dG/dx
        const float d2 = (x * x / (f.sigma * f.sigma) - 1.0f) * g;  // shape of d2G/dx2
        f.gauss[i] = g;
        f.d1[i] = d1;
        f.d2[i] = d2;
        gSum += g;
        (d1 > 0.0f ? d1Pos : d1Neg) += std::abs(d1);
        (d2 > 0.0f ? d2Pos : d2Neg) += std::abs(d2);
    }
    for (int i = 0; i < width; ++i) {
        f.gauss[i] /= gSum;
        f.d1[i] /= f.d1[i] > 0.0f ? d1Pos : d1Neg;
        f.d2[i] /= f.d2[i] > 0.0f ? d2Pos : d2Neg;
    }
    return f;
}

}  // namespace aamap::metrics::flip
