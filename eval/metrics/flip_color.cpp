#include "eval/metrics/flip_color.h"

#include <algorithm>
#include <cmath>

#include <glm/common.hpp>
#include <glm/vec4.hpp>
#include <tbb/parallel_for.h>

namespace aamap::metrics::flip {
namespace {

// sRGB primaries, D65 white (IEC 61966-2-1), as exact ratios so both directions agree.
constexpr float kRgbToXyz[3][3] = {
    {10135552.0f / 24577794.0f, 8788810.0f / 24577794.0f, 4435075.0f / 24577794.0f},
    {2613072.0f / 12288897.0f, 8788810.0f / 12288897.0f, 887015.0f / 12288897.0f},
    {1425312.0f / 73733382.0f, 8788810.0f / 73733382.0f, 70074185.0f / 73733382.0f},
};
constexpr float kXyzToRgb[3][3] = {
    {3.241003275f, -1.537398934f, -0.498615861f},
    {-0.969224334f, 1.875930071f, 0.041554224f},
    {0.055639423f, -0.204011202f, 1.057148933f},
};
// The white point: XYZ of linear RGB (1,1,1).
constexpr glm::vec3 kWhite{0.950428545f, 1.0f, 1.088900371f};
constexpr glm::vec3 kInvWhite{1.052156925f, 1.0f, 0.918357670f};

glm::vec3 mul(const float (&m)[3][3], glm::vec3 v) {
    return {m[0][0] * v.x + m[0][1] * v.y + m[0][2] * v.z, m[1][0] * v.x + m[1][1] * v.y + m[1][2] * v.z,
            m[2][0] * v.x + m[2][1] * v.y + m[2][2] * v.z};
}

// The L*a*b* companding function: cube root above (6/29)^3, linear below.
float labF(float t) {
    constexpr float delta = 6.0f / 29.0f;
    constexpr float deltaCube = delta * delta * delta;
    return t > deltaCube ? std::cbrt(t) : t / (3.0f * delta * delta) + 4.0f / 29.0f;
}

}  // namespace

float srgbToLinear(float c) { return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f); }

glm::vec3 linearRgbToXyz(glm::vec3 rgb) { return mul(kRgbToXyz, rgb); }
glm::vec3 xyzToLinearRgb(glm::vec3 xyz) { return mul(kXyzToRgb, xyz); }

glm::vec3 xyzToYcxcz(glm::vec3 xyz) {
    const glm::vec3 n = xyz * kInvWhite;
    return {116.0f * n.y - 16.0f, 500.0f * (n.x - n.y), 200.0f * (n.y - n.z)};
}

glm::vec3 ycxczToXyz(glm::vec3 ycc) {
    const float y = (ycc.x + 16.0f) / 116.0f;
    return glm::vec3(y + ycc.y / 500.0f, y, y - ycc.z / 200.0f) * kWhite;
}

glm::vec3 xyzToLab(glm::vec3 xyz) {
    const glm::vec3 n = xyz * kInvWhite;
    const float fx = labF(n.x), fy = labF(n.y), fz = labF(n.z);
    return {116.0f * fy - 16.0f, 500.0f * (fx - fy), 200.0f * (fy - fz)};
}

float hyab(glm::vec3 a, glm::vec3 b) {
    const float da = a.y - b.y;
    const float db = a.z - b.z;
    return std::abs(a.x - b.x) + std::sqrt(da * da + db * db);
}

float maxColourDistance() {
    const glm::vec3 green = hunt(xyzToLab(linearRgbToXyz({0.0f, 1.0f, 0.0f})));
    const glm::vec3 blue = hunt(xyzToLab(linearRgbToXyz({0.0f, 0.0f, 1.0f})));
    return std::pow(hyab(green, blue), kQc);
}

float redistribute(float powered) {
    static const float cmax = maxColourDistance();
    const float knee = kPc * cmax;
    const float e = powered < knee ? powered * kPt / knee : kPt + (powered - knee) / (cmax - knee) * (1.0f - kPt);
    return std::min(e, 1.0f);  // guard only: cmax is the largest distance inside the RGB cube
}

ImageRGB spatialFilter(const ImageRGB& ycc, const SpatialFilters& f) {
    const int w = ycc.width(), h = ycc.height(), r = f.radius;
    // Horizontal pass: (Y, Cx, Cz with term 1, Cz with term 2).
    Image<glm::vec4> tmp(w, h);
    tbb::parallel_for(0, h, [&](int y) {
        for (int x = 0; x < w; ++x) {
            glm::vec4 acc(0.0f);
            for (int i = -r; i <= r; ++i) {
                const glm::vec3 p = ycc.at(clampIndex(x + i, w), y);
                const int k = i + r;
                acc += glm::vec4(f.y[k] * p.x, f.cx[k] * p.y, f.cz1[k] * p.z, f.cz2[k] * p.z);
            }
            tmp.at(x, y) = acc;
        }
    });
    // Vertical pass, then the two Cz terms are summed.
    ImageRGB out(w, h);
    tbb::parallel_for(0, h, [&](int y) {
        for (int x = 0; x < w; ++x) {
            glm::vec4 acc(0.0f);
            for (int i = -r; i <= r; ++i) {
                const glm::vec4 p = tmp.at(x, clampIndex(y + i, h));
                const int k = i + r;
                acc += glm::vec4(f.y[k] * p.x, f.cx[k] * p.y, f.cz1[k] * p.z, f.cz2[k] * p.w);
            }
            out.at(x, y) = {acc.x, acc.y, acc.z + acc.w};
        }
    });
    return out;
}

ImageGrey colourDifference(const ImageRGB& refYcc, const ImageRGB& testYcc, const SpatialFilters& filters) {
    const ImageRGB ref = spatialFilter(refYcc, filters);
    const ImageRGB test = spatialFilter(testYcc, filters);
    // Filtered colour -> displayable linear RGB -> Hunt-adjusted L*a*b*.
    auto toHuntLab = [](glm::vec3 ycc) {
        const glm::vec3 rgb = glm::clamp(xyzToLinearRgb(ycxczToXyz(ycc)), 0.0f, 1.0f);
        return hunt(xyzToLab(linearRgbToXyz(rgb)));
    };
    ImageGrey out(ref.width(), ref.height());
    tbb::parallel_for(0, ref.height(), [&](int y) {
        for (int x = 0; x < ref.width(); ++x) {
            const float d = hyab(toHuntLab(ref.at(x, y)), toHuntLab(test.at(x, y)));
            out.at(x, y) = redistribute(std::pow(d, kQc));
        }
    });
    return out;
}

}  // namespace aamap::metrics::flip
