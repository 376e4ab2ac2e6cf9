#include "eval/metrics/flip_feature.h"

#include <algorithm>
#include <cmath>

#include <glm/vec3.hpp>
#include <tbb/parallel_for.h>

namespace aamap::metrics::flip {

Image<glm::vec2> featureResponse(const ImageRGB& ycc, const FeatureFilter& f) {
    const int w = ycc.width(), h = ycc.height(), r = f.radius;
    // Horizontal pass: (dG/dx * Y, d2G/dx2 * Y, G * Y). The 2D filters are separable products:
    // dx = G(y) * G'(x), dy = G'(y) * G(x), and likewise for the second derivatives.
    ImageRGB tmp(w, h);
    tbb::parallel_for(0, h, [&](int y) {
        for (int x = 0; x < w; ++x) {
            glm::vec3 acc(0.0f);
            for (int i = -r; i <= r; ++i) {
                const float v = (ycc.at(clampIndex(x + i, w), y).x + 16.0f) / 116.0f;
                const int k = i + r;
                acc += glm::vec3(f.d1[k] * v, f.d2[k] * v, f.gauss[k] * v);
            }
            tmp.at(x, y) = acc;
        }
    });
    Image<glm::vec2> out(w, h);
    tbb::parallel_for(0, h, [&](int y) {
        for (int x = 0; x < w; ++x) {
            float dx = 0.0f, dxx = 0.0f, dy = 0.0f, dyy = 0.0f;
            for (int i = -r; i <= r; ++i) {
                const glm::vec3 p = tmp.at(x, clampIndex(y + i, h));
                const int k = i + r;
                dx += f.gauss[k] * p.x;
                dxx += f.gauss[k] * p.y;
                dy += f.d1[k] * p.z;
                dyy += f.d2[k] * p.z;
            }
            out.at(x, y) = {std::sqrt(dx * dx + dy * dy), std::sqrt(dxx * dxx + dyy * dyy)};
        }
    });
    return out;
}

ImageGrey featureDifference(const ImageRGB& refYcc, const ImageRGB& testYcc, const FeatureFilter& filter) {
    const Image<glm::vec2> ref = featureResponse(refYcc, filter);
    const Image<glm::vec2> test = featureResponse(testYcc, filter);
    const float invSqrt2 = 1.0f / std::sqrt(2.0f);
    ImageGrey out(ref.width(), ref.height());
    for (std::size_t i = 0; i < ref.size(); ++i) {
        const glm::vec2 a = ref.pixels()[i];
        const glm::vec2 b = test.pixels()[i];
        const float d = std::max(std::abs(a.x - b.x), std::abs(a.y - b.y));
        out.pixels()[i] = std::pow(invSqrt2 * d, kQf);
    }
    return out;
}

}  // namespace aamap::metrics::flip
