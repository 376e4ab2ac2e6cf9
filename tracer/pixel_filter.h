#pragma once
// Pixel reconstruction filters, applied in one of two ways (docs/tracer.md, "Pixel filters"):
// - convolution (the default): the strategy renders box pixels, and the finished image is
//   convolved with the filter integrated over each pixel cell. Neighbouring pixels then share
//   their samples, as a splatting film does, which importance sampling cannot: less noise for
//   the same rays.
// - importance (as pbrt-v4 does): each primary ray's film position is drawn from the filter
//   itself, so every sample weighs 1 and a pixel stays the plain mean of its samples. Separable
//   filters: each axis maps its stratified number through the inverse of the 1D filter's
//   cumulative distribution, which is monotone, so k x k strata of [0,1)^2 stay k x k cells of
//   equal filter weight.
#include <string>
#include <vector>

#include <glm/vec2.hpp>

#include "core/image.h"

namespace aamap {

enum class PixelFilterType {
    Box,       // constant over [-r, r]: r = 0.5 is the pixel itself (the default)
    Tent,      // 1 - |x| / r (pbrt's triangle filter, Mitsuba's tent)
    Gaussian,  // exp(-x^2 / (2 sigma^2)) - exp(-r^2 / (2 sigma^2)), clamped at 0 (pbrt, Mitsuba)
};
// image.filter's names, declared with the schema (tracer/shading_params.cpp).
const char* toString(PixelFilterType type);
bool parse(const std::string& name, PixelFilterType& type);  // false for an unknown name

enum class PixelFilterMode {
    Convolution,  // box pixels rendered, then the image convolved with the pixel-integrated filter
    Importance,   // film positions drawn from the filter; each pixel the mean of its own samples
};
const char* toString(PixelFilterMode mode);
bool parse(const std::string& name, PixelFilterMode& mode);  // false for an unknown name

struct PixelFilterSettings {
    PixelFilterType type = PixelFilterType::Box;
    float radius = 0.0f;  // in pixels; 0 chooses the filter's own: box 0.5, tent 1, gaussian 4 sigma
    float stddev = 0.5f;  // gaussian only: sigma in pixels (Mitsuba's default)
    PixelFilterMode mode = PixelFilterMode::Convolution;
    bool operator==(const PixelFilterSettings&) const = default;
};

class PixelFilter {
public:
    explicit PixelFilter(const PixelFilterSettings& settings = {});

    PixelFilterType type() const { return type_; }
    float radius() const { return radius_; }
    // True for the default box of radius 0.5: film positions are then the stratified numbers
    // themselves, bit for bit.
    bool isPixelBox() const { return pixelBox_; }

    // The 1D filter at offset x from the pixel centre, not normalised (0 outside [-r, r]).
    double evaluate1D(double x) const;
    // Its cumulative distribution from -r, normalised: 0 at -r, 1 at r.
    double cdf1D(double x) const;

    // The film position, relative to the pixel's lower corner (pixel units), of the stratified
    // numbers u in [0,1)^2: u itself for the pixel box, else 0.5 + F^-1(u) per axis.
    glm::vec2 positionInPixel(glm::vec2 u) const {
        if (pixelBox_) return u;
        return {0.5f + offset(u.x), 0.5f + offset(u.y)};
    }
    // F^-1(u): the offset from the pixel centre whose cumulative weight is u, in [-r, r].
    float offset(float u) const;

    // The filter's weight over each pixel cell, per axis: element reach() + d is the weight of
    // the pixel d away, F(d + 1/2) - F(d - 1/2). Symmetric; sums to 1.
    const std::vector<double>& pixelKernel() const { return kernel_; }
    int reach() const { return static_cast<int>(kernel_.size() / 2); }
    // The image convolved with pixelKernel() along both axes. At the border the weights of the
    // pixels inside are renormalised (per axis, which is exact for the separable kernel over the
    // rectangle of pixels inside), so a constant image stays that constant.
    ImageRGB convolve(const ImageRGB& image) const;

private:
    double gaussianIntegral(double x) const;  // from -r to x, not normalised

    PixelFilterType type_;
    float radius_;
    double sigma_;
    bool pixelBox_;
    // Gaussian: the exact CDF (erf) and the filter at kSteps + 1 equal steps of x over [-r, r].
    // offset() finds u's step and inverts the CDF of a filter linear across it: a lookup and a
    // square root per sample instead of a solve, within 1e-7 of the exact CDF
    // (tests/tracer/test_pixel_filter.cpp).
    static constexpr int kSteps = 1024;
    std::vector<double> cdf_, pdf_, fourA_;
    // guide_[j]: the step holding u = j / kGuide, so that a lookup searches the few steps between
    // two guides instead of the whole table (a full binary search mispredicts at every level).
    static constexpr int kGuide = 1024;
    std::vector<int> guide_;
    int stepHolding(double u, int lo, int hi) const;  // the last i in [lo, hi] with cdf_[i] <= u
    double gaussianTotal_ = 1.0;
    std::vector<double> kernel_;  // pixelKernel()
};

}  // namespace aamap
