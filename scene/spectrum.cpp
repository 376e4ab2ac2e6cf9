#include "scene/spectrum.h"

#include <algorithm>
#include <cmath>
#include <iterator>

#include <glm/mat3x3.hpp>

namespace aamap {
namespace {

// One asymmetric Gaussian lobe of the colour-matching fit.
double lobe(double nm, double mean, double sigmaBelow, double sigmaAbove) {
    const double t = (nm - mean) / (nm < mean ? sigmaBelow : sigmaAbove);
    return std::exp(-0.5 * t * t);
}

glm::dvec3 cie1931(double nm) {
    const double x = 1.056 * lobe(nm, 599.8, 37.9, 31.0) + 0.362 * lobe(nm, 442.0, 16.0, 26.7) -
                     0.065 * lobe(nm, 501.1, 20.4, 26.2);
    const double y = 0.821 * lobe(nm, 568.8, 46.9, 40.5) + 0.286 * lobe(nm, 530.9, 16.3, 31.1);
    const double z = 1.217 * lobe(nm, 437.0, 11.8, 36.0) + 0.681 * lobe(nm, 459.0, 26.0, 13.8);
    return {x, y, z};
}

// The CIE standard illuminant D65, relative spectral power at 300, 310, ..., 830 nm (CIE's own
// 5 nm table is this one linearly interpolated).
constexpr double kD65[] = {0.0341,  3.2945,  20.236,  37.0535, 39.9488, 44.9117, 46.6383, 52.0891, 49.9755,
                           54.6482, 82.7549, 91.486,  93.4318, 86.6823, 104.865, 117.008, 117.812, 114.861,
                           115.923, 108.811, 109.354, 107.802, 104.79,  107.689, 104.405, 104.046, 100.0,
                           96.3342, 95.788,  88.6856, 90.0062, 89.5991, 87.6987, 83.2886, 83.6992, 80.0268,
                           80.2146, 82.2778, 78.2842, 69.7213, 71.6091, 74.349,  61.604,  69.8856, 75.087,
                           63.5927, 46.4182, 66.8054, 63.3828, 64.304,  59.4519, 51.959,  57.4406, 60.3125};

double d65(double nm) {
    const double x = std::clamp((nm - 300.0) / 10.0, 0.0, static_cast<double>(std::size(kD65) - 1));
    const auto i = std::min(static_cast<std::size_t>(x), std::size(kD65) - 2);
    const double t = x - static_cast<double>(i);
    return kD65[i] + t * (kD65[i + 1] - kD65[i]);
}

glm::dvec3 xyzToLinearSrgb(const glm::dvec3& c) {
    return {3.2404542 * c.x - 1.5371385 * c.y - 0.4985314 * c.z, -0.9692660 * c.x + 1.8760108 * c.y + 0.0415560 * c.z,
            0.0556434 * c.x - 0.2040259 * c.y + 1.0572252 * c.z};
}

template <class F>
glm::dvec3 project(F&& value) {
    glm::dvec3 xyz(0.0);
    for (double nm = 360.0; nm <= 830.0; nm += 1.0) xyz += value(nm) * cie1931(nm);
    return xyzToLinearSrgb(xyz);
}

}  // namespace

glm::vec3 spectrumToRgb(std::vector<std::pair<double, double>> samples, SpectrumUse use) {
    if (samples.empty()) return glm::vec3(0.0f);
    std::sort(samples.begin(), samples.end());
    // Zero outside the samples, as Mitsuba 3 reads a spectrum in its RGB modes.
    const auto at = [&](double nm) {
        if (nm < samples.front().first || nm > samples.back().first) return 0.0;
        if (nm == samples.front().first) return samples.front().second;
        if (nm == samples.back().first) return samples.back().second;
        const auto hi = std::upper_bound(samples.begin(), samples.end(), std::make_pair(nm, -HUGE_VAL));
        const auto lo = hi - 1;
        const double span = hi->first - lo->first;
        const double t = span > 0.0 ? (nm - lo->first) / span : 0.0;
        return lo->second + t * (hi->second - lo->second);
    };
    if (use == SpectrumUse::Emission) {
        static const double yIntegral = [] {
            double y = 0.0;
            for (double nm = 360.0; nm <= 830.0; nm += 1.0) y += cie1931(nm).y;
            return y;
        }();
        return glm::vec3(glm::max(project(at) / yIntegral, glm::dvec3(0.0)));
    }
    // A reflectance is seen under D65, normalised so that a constant 1 has Y = 1, and clamped to
    // [0, 1] (a reflectance reflects no more than arrives); an unbounded constant at 0 only.
    static const double d65Y = [] {
        double y = 0.0;
        for (double nm = 360.0; nm <= 830.0; nm += 1.0) y += d65(nm) * cie1931(nm).y;
        return y;
    }();
    const glm::dvec3 rgb = glm::max(project([&](double nm) { return at(nm) * d65(nm); }) / d65Y, glm::dvec3(0.0));
    return glm::vec3(use == SpectrumUse::Unbounded ? rgb : glm::min(rgb, glm::dvec3(1.0)));
}

}  // namespace aamap
