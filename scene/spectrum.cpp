#include "scene/spectrum.h"

#include <algorithm>
#include <cmath>

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
    const bool emission = use == SpectrumUse::Emission;
    const auto at = [&](double nm) {
        if (nm < samples.front().first || nm > samples.back().first) {
            if (emission) return 0.0;
            return nm < samples.front().first ? samples.front().second : samples.back().second;
        }
        if (nm == samples.front().first) return samples.front().second;
        if (nm == samples.back().first) return samples.back().second;
        const auto hi = std::upper_bound(samples.begin(), samples.end(), std::make_pair(nm, -HUGE_VAL));
        const auto lo = hi - 1;
        const double span = hi->first - lo->first;
        const double t = span > 0.0 ? (nm - lo->first) / span : 0.0;
        return lo->second + t * (hi->second - lo->second);
    };
    if (emission) {
        static const double yIntegral = [] {
            double y = 0.0;
            for (double nm = 360.0; nm <= 830.0; nm += 1.0) y += cie1931(nm).y;
            return y;
        }();
        return glm::vec3(project(at) / yIntegral);
    }
    static const glm::dvec3 white = project([](double) { return 1.0; });
    return glm::vec3(project(at) / white);
}

}  // namespace aamap
