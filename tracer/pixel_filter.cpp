#include "tracer/pixel_filter.h"

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <stdexcept>

#include <fmt/format.h>
#include <glm/vec3.hpp>

namespace aamap {
namespace {

constexpr double kSqrtHalfPi = 1.2533141373155003;  // sqrt(pi / 2)

// The radius a setting resolves to: its own, or the filter's default.
float resolvedRadius(const PixelFilterSettings& s) {
    if (s.radius != 0.0f) return s.radius;  // negative: refused by PixelFilter
    switch (s.type) {
        case PixelFilterType::Box: return 0.5f;
        case PixelFilterType::Tent: return 1.0f;
        case PixelFilterType::Gaussian: return 4.0f * s.stddev;
    }
    return 0.5f;
}

}  // namespace

PixelFilter::PixelFilter(const PixelFilterSettings& settings)
    : type_(settings.type), radius_(resolvedRadius(settings)), sigma_(settings.stddev) {
    if (!(radius_ > 0.0f) || !std::isfinite(radius_) || (type_ == PixelFilterType::Gaussian && !(sigma_ > 0.0)))
        throw std::invalid_argument(
            fmt::format("pixel filter {}: radius {} and stddev {} must be > 0", toString(type_), radius_, sigma_));
    pixelBox_ = type_ == PixelFilterType::Box && radius_ == 0.5f;
    if (type_ == PixelFilterType::Gaussian) {
        gaussianTotal_ = gaussianIntegral(radius_);
        cdf_.resize(kSteps + 1);
        pdf_.resize(kSteps + 1);
        for (int i = 0; i <= kSteps; ++i) {
            const double x = radius_ * (2.0 * i / kSteps - 1.0);
            cdf_[static_cast<std::size_t>(i)] = cdf1D(x);
            pdf_[static_cast<std::size_t>(i)] = evaluate1D(x) / gaussianTotal_;
        }
        // Per step, 4 a of the quadratic that offset() solves (a: the filter's slope across the
        // step, halved), so that a lookup divides only once.
        const double h = 2.0 * radius_ / kSteps;
        fourA_.resize(kSteps);
        for (int i = 0; i < kSteps; ++i) {
            const auto k = static_cast<std::size_t>(i);
            fourA_[k] = 4.0 * (0.5 * (pdf_[k + 1] - pdf_[k]) / h);
        }
        guide_.resize(kGuide + 1);
        for (int j = 0; j <= kGuide; ++j) guide_[static_cast<std::size_t>(j)] = stepHolding(static_cast<double>(j) / kGuide, 0, kSteps - 1);
    }
    // Pixel d's cell [d - 1/2, d + 1/2] meets [-r, r] for |d| < r + 1/2.
    const int reach = std::max(0, static_cast<int>(std::ceil(static_cast<double>(radius_) - 0.5)));
    kernel_.resize(static_cast<std::size_t>(2 * reach + 1));
    for (int d = -reach; d <= reach; ++d)
        kernel_[static_cast<std::size_t>(d + reach)] = cdf1D(d + 0.5) - cdf1D(d - 0.5);
}

ImageRGB PixelFilter::convolve(const ImageRGB& image) const {
    const int W = image.width(), H = image.height(), R = reach();
    if (R == 0 || image.empty()) return image;
    // One axis: out(i) = sum over the taps inside [0, n) of K[d] in(i + d), over their weight.
    auto pass = [&](const ImageRGB& in, bool alongX) {
        ImageRGB out(W, H);
        const int n = alongX ? W : H;
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < W; ++x) {
                const int i = alongX ? x : y;
                glm::dvec3 sum(0.0);
                double weight = 0.0;
                for (int d = std::max(-R, -i); d <= std::min(R, n - 1 - i); ++d) {
                    const double k = kernel_[static_cast<std::size_t>(d + R)];
                    sum += k * glm::dvec3(alongX ? in.at(x + d, y) : in.at(x, y + d));
                    weight += k;
                }
                out.at(x, y) = glm::vec3(weight > 0.0 ? sum / weight : glm::dvec3(0.0));
            }
        return out;
    };
    return pass(pass(image, true), false);
}

int PixelFilter::stepHolding(double u, int lo, int hi) const {
    // cdf_ is non-decreasing: the answer for u lies between those of the guides around it.
    const auto first = cdf_.begin() + lo + 1, last = cdf_.begin() + hi + 1;
    return static_cast<int>(std::upper_bound(first, last, u) - cdf_.begin()) - 1;
}

double PixelFilter::gaussianIntegral(double x) const {
    // The integral of exp(-t^2 / 2 sigma^2) - exp(-r^2 / 2 sigma^2) from -r to x.
    const double r = radius_, s = sigma_ * std::sqrt(2.0);
    const double bias = std::exp(-0.5 * r * r / (sigma_ * sigma_));
    return sigma_ * kSqrtHalfPi * (std::erf(x / s) + std::erf(r / s)) - bias * (x + r);
}

double PixelFilter::evaluate1D(double x) const {
    const double r = radius_;
    if (!(std::abs(x) <= r)) return 0.0;
    switch (type_) {
        case PixelFilterType::Box: return 1.0;
        case PixelFilterType::Tent: return 1.0 - std::abs(x) / r;
        case PixelFilterType::Gaussian: {
            const double a = -0.5 / (sigma_ * sigma_);
            return std::max(0.0, std::exp(a * x * x) - std::exp(a * r * r));
        }
    }
    return 0.0;
}

double PixelFilter::cdf1D(double x) const {
    const double r = radius_;
    x = std::clamp(x, -r, r);
    switch (type_) {
        case PixelFilterType::Box: return (x + r) / (2.0 * r);
        case PixelFilterType::Tent: {
            const double t = 1.0 - std::abs(x) / r;  // mass beyond |x| on that side is t^2 / 2
            return x < 0.0 ? 0.5 * t * t : 1.0 - 0.5 * t * t;
        }
        case PixelFilterType::Gaussian: return gaussianIntegral(x) / gaussianTotal_;
    }
    return 0.0;
}

float PixelFilter::offset(float uf) const {
    const double u = std::clamp(static_cast<double>(uf), 0.0, 1.0);
    const double r = radius_;
    switch (type_) {
        case PixelFilterType::Box: return static_cast<float>((2.0 * u - 1.0) * r);
        case PixelFilterType::Tent:
            return static_cast<float>(u < 0.5 ? r * (std::sqrt(2.0 * u) - 1.0) : r * (1.0 - std::sqrt(2.0 * (1.0 - u))));
        case PixelFilterType::Gaussian: {
            // The step holding u, then the exact inverse of the CDF of a filter linear across
            // the step (its values at both ends): a d^2 + b d = u - F_i, in the stable form.
            const int j = std::min(static_cast<int>(u * kGuide), kGuide - 1);
            const int i = stepHolding(u, guide_[static_cast<std::size_t>(j)], guide_[static_cast<std::size_t>(j) + 1]);
            const double h = 2.0 * r / kSteps;
            const double du = u - cdf_[static_cast<std::size_t>(i)];
            const double b = pdf_[static_cast<std::size_t>(i)];
            const double disc = std::max(0.0, b * b + fourA_[static_cast<std::size_t>(i)] * du);
            const double denom = b + std::sqrt(disc);
            const double d = denom > 0.0 ? 2.0 * du / denom : 0.0;
            return static_cast<float>(std::clamp(-r + h * i + std::clamp(d, 0.0, h), -r, r));
        }
    }
    return 0.0f;
}

}  // namespace aamap
