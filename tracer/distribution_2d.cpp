#include "tracer/distribution_2d.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>
#include <glm/common.hpp>

namespace aamap {
namespace {

// guide[k] for k in [0, n): the interval holding k / n, i.e. the largest i with cdf[i] <= k / n
// (at most n - 1). It starts the search in invert() one or two steps from the answer, where a
// binary search over the whole CDF mispredicts a branch at every level.
void buildGuide(const float* cdf, int n, int* guide) {
    int i = 0;
    for (int k = 0; k < n; ++k) {
        const float t = static_cast<float>(k) / static_cast<float>(n);
        while (i + 1 < n && cdf[i + 1] <= t) ++i;
        guide[k] = i;
    }
}

// The index i with cdf[i] <= u < cdf[i + 1] among the n intervals of cdf[0..n], skipping empty
// ones; u is rescaled to [0,1) within it. The same index as a binary search for the last
// cdf[i] <= u: the guide only picks where the scan starts, and the scan goes both ways.
int invert(const float* cdf, const int* guide, int n, float& u) {
    const float x = u * static_cast<float>(n);  // compared before the cast: a NaN starts at 0
    int i = guide[x > 0.0f ? (x < static_cast<float>(n) ? static_cast<int>(x) : n - 1) : 0];
    while (i > 0 && cdf[i] > u) --i;
    while (i + 1 < n && cdf[i + 1] <= u) ++i;
    while (i > 0 && !(cdf[i + 1] > cdf[i])) --i;  // u at 1 - ulp on a trailing empty interval
    const float width = cdf[i + 1] - cdf[i];
    u = width > 0.0f ? std::clamp((u - cdf[i]) / width, 0.0f, 0x1.fffffep-1f) : 0.0f;
    return i;
}

// Fills cdf[0..n] from w[0..n); a zero total gives the uniform CDF. Returns the total.
double buildCdf(const float* w, int n, float* cdf) {
    double total = 0.0;
    for (int i = 0; i < n; ++i) total += w[i];
    double running = 0.0;
    cdf[0] = 0.0f;
    for (int i = 0; i < n; ++i) {
        running += w[i];
        cdf[i + 1] = total > 0.0 ? static_cast<float>(running / total) : static_cast<float>(i + 1) / n;
    }
    cdf[n] = 1.0f;
    return total;
}

}  // namespace

Distribution2D::Distribution2D(const std::vector<float>& weights, int width, int height)
    : width_(width), height_(height) {
    if (width < 1 || height < 1 || weights.size() != static_cast<std::size_t>(width) * height)
        throw std::invalid_argument(fmt::format("Distribution2D: {} weights for a {} x {} grid", weights.size(), width,
                                                height));
    weights_.resize(weights.size());
    for (std::size_t i = 0; i < weights.size(); ++i)
        weights_[i] = std::isfinite(weights[i]) && weights[i] > 0.0f ? weights[i] : 0.0f;
    conditional_.resize(static_cast<std::size_t>(height) * (width + 1));
    std::vector<float> rowTotals(height);
    double total = 0.0;
    for (int y = 0; y < height; ++y) {
        const double t = buildCdf(&weights_[static_cast<std::size_t>(y) * width], width,
                                  &conditional_[static_cast<std::size_t>(y) * (width + 1)]);
        rowTotals[y] = static_cast<float>(t);
        total += t;
    }
    marginal_.resize(height + 1);
    buildCdf(rowTotals.data(), height, marginal_.data());
    marginalGuide_.resize(height);
    buildGuide(marginal_.data(), height, marginalGuide_.data());
    conditionalGuide_.resize(static_cast<std::size_t>(height) * width);
    for (int y = 0; y < height; ++y)
        buildGuide(&conditional_[static_cast<std::size_t>(y) * (width + 1)], width,
                   &conditionalGuide_[static_cast<std::size_t>(y) * width]);
    empty_ = !(total > 0.0);
    scale_ = empty_ ? 0.0 : static_cast<double>(width) * height / total;
}

Distribution2D::Sample Distribution2D::sample(glm::vec2 u) const {
    Sample s{};
    if (empty_) return s;
    s.row = invert(marginal_.data(), marginalGuide_.data(), height_, u.y);
    s.column = invert(&conditional_[static_cast<std::size_t>(s.row) * (width_ + 1)],
                      &conditionalGuide_[static_cast<std::size_t>(s.row) * width_], width_, u.x);
    s.point = {(static_cast<float>(s.column) + u.x) / static_cast<float>(width_),
               (static_cast<float>(s.row) + u.y) / static_cast<float>(height_)};
    s.point = glm::min(s.point, glm::vec2(0x1.fffffep-1f));
    s.pdf = pdf(s.column, s.row);
    return s;
}

float Distribution2D::pdf(int column, int row) const {
    return static_cast<float>(weights_[static_cast<std::size_t>(row) * width_ + column] * scale_);
}

}  // namespace aamap
