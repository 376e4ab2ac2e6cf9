#include "tracer/pixel_filter.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

namespace aamap {
namespace {

constexpr double kSqrtHalfPi = 1.2533141373155003;  // sqrt(pi / 2)
constexpr int kTableSteps = 64;                      // brackets for the Gaussian's inversion

}  // namespace

const char* toString(PixelFilterType type) {
    switch (type) {
        case PixelFilterType::Box: return "box";
        case PixelFilterType::Tent: return "tent";
        case PixelFilterType::Gaussian: return "gaussian";
    }
    return "?";
}

bool parse(const std::string& name, PixelFilterType& type) {
    for (PixelFilterType t : {PixelFilterType::Box, PixelFilterType::Tent, PixelFilterType::Gaussian})
        if (name == toString(t)) {
            type = t;
            return true;
        }
    return false;
}

float resolvedRadius(const PixelFilterSettings& s) {
    if (s.radius != 0.0f) return s.radius;  // negative: refused by PixelFilter
    switch (s.type) {
        case PixelFilterType::Box: return 0.5f;
        case PixelFilterType::Tent: return 1.0f;
        case PixelFilterType::Gaussian: return 4.0f * s.stddev;
    }
    return 0.5f;
}

PixelFilter::PixelFilter(const PixelFilterSettings& settings)
    : type_(settings.type), radius_(resolvedRadius(settings)), sigma_(settings.stddev) {
    if (!(radius_ > 0.0f) || !std::isfinite(radius_) || (type_ == PixelFilterType::Gaussian && !(sigma_ > 0.0)))
        throw std::invalid_argument(
            fmt::format("pixel filter {}: radius {} and stddev {} must be > 0", toString(type_), radius_, sigma_));
    pixelBox_ = type_ == PixelFilterType::Box && radius_ == 0.5f;
    if (type_ == PixelFilterType::Gaussian) {
        gaussianTotal_ = gaussianIntegral(radius_);
        table_.resize(kTableSteps + 1);
        for (int i = 0; i <= kTableSteps; ++i)
            table_[static_cast<std::size_t>(i)] = cdf1D(radius_ * (2.0 * i / kTableSteps - 1.0));
    }
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
            // The table brackets u; Newton's method on the exact CDF inside the bracket, falling
            // back to bisection when a step would leave it.
            const auto it = std::upper_bound(table_.begin(), table_.end(), u);
            const int hi = std::clamp(static_cast<int>(it - table_.begin()), 1, kTableSteps);
            double lo = r * (2.0 * (hi - 1) / kTableSteps - 1.0), up = r * (2.0 * hi / kTableSteps - 1.0);
            const double clo = table_[static_cast<std::size_t>(hi - 1)], cup = table_[static_cast<std::size_t>(hi)];
            double x = cup > clo ? lo + (up - lo) * (u - clo) / (cup - clo) : 0.5 * (lo + up);
            for (int i = 0; i < 64; ++i) {
                const double f = cdf1D(x) - u;
                if (f == 0.0) break;
                if (f > 0.0) up = x; else lo = x;
                const double pdf = evaluate1D(x) / gaussianTotal_;
                double next = pdf > 0.0 ? x - f / pdf : 0.5 * (lo + up);
                if (!(next > lo && next < up)) next = 0.5 * (lo + up);
                const bool converged = std::abs(next - x) < 1e-10 * r;
                x = next;
                if (converged) break;
            }
            return static_cast<float>(x);
        }
    }
    return 0.0f;
}

}  // namespace aamap
