// Supersample and filter, as rendering with rpict at f times the resolution and reducing with
// pfilt: each pixel is split into f x f sub-pixels of n x n jittered strata (strata of the pixel's
// fn x fn grid, so f = 1 is uniform sampling), then each output pixel is a weighted mean of the
// sub-pixel means. Box: its own f x f sub-pixels, equal weights (pfilt -x /f -y /f). Gaussian:
// every sub-pixel within 2r output pixels of its centre, weight exp(-(d/r)^2) (pfilt -r), weights
// normalised over the sub-pixels inside the image.
#include <cmath>
#include <vector>

#include <fmt/format.h>

#include "tracer/strategies/strategies.h"

namespace aamap {
namespace {

enum class DownFilter { Box, Gaussian };
const char* toString(DownFilter filter) { return filter == DownFilter::Gaussian ? "gaussian" : "box"; }

class SupersampleStrategy final : public SamplingStrategy {
public:
    SupersampleStrategy(int n, int factor, DownFilter filter, double radius)
        : n_(n), f_(factor), filter_(filter), radius_(radius) {}
    int maxRaysPerPixel() const override { return f_ * f_ * n_ * n_; }
    int tilePhases() const override { return 2; }
    std::string describe() const override {
        return fmt::format("supersample n={} factor={} filter={} radius={}", n_, f_, toString(filter_), radius_);
    }

    void render(const SampleSource& source, const Scheduler& scheduler, StrategyImages& out) const override {
        const int W = source.width(), H = source.height(), SW = W * f_;
        const int K = f_ * n_;
        ImageRGB sub(SW, H * f_);
        scheduler.tiles([&](int x0, int y0, int x1, int y1) {
            for (int y = y0; y < y1; ++y)
                for (int x = x0; x < x1; ++x) {
                    for (int j = 0; j < f_; ++j)
                        for (int i = 0; i < f_; ++i) sub.at(x * f_ + i, y * f_ + j) = subPixel(source, x, y, i, j, K);
                    out.primaryRays.at(x, y) = static_cast<std::uint16_t>(K * K);
                    out.traced.at(x, y) = 1;
                }
        });
        scheduler.tiles([&](int x0, int y0, int x1, int y1) {
            for (int y = y0; y < y1; ++y)
                for (int x = x0; x < x1; ++x) out.image.at(x, y) = filtered(sub, x, y);
        });
    }

private:
    glm::vec3 subPixel(const SampleSource& source, int x, int y, int i, int j, int K) const {
        glm::dvec3 sum(0.0);
        int kept = 0;
        for (int sy = 0; sy < n_; ++sy)
            for (int sx = 0; sx < n_; ++sx) {
                const PrimarySample s = source.sample(x, y, i * n_ + sx, j * n_ + sy, K, false);
                if (!s.finite) continue;
                sum += glm::dvec3(s.radiance);
                ++kept;
            }
        return kept > 0 ? glm::vec3(sum / static_cast<double>(kept)) : glm::vec3(0.0f);
    }

    glm::vec3 filtered(const ImageRGB& sub, int x, int y) const {
        glm::dvec3 sum(0.0);
        double weights = 0.0;
        if (filter_ == DownFilter::Box) return box(sub, x, y);
        const int reach = static_cast<int>(std::ceil(2.0 * radius_ * f_));  // in sub-pixels
        const double cx = x + 0.5, cy = y + 0.5;
        for (int Y = y * f_ - reach; Y < (y + 1) * f_ + reach; ++Y) {
            if (Y < 0 || Y >= sub.height()) continue;
            for (int X = x * f_ - reach; X < (x + 1) * f_ + reach; ++X) {
                if (X < 0 || X >= sub.width()) continue;
                const double dx = (X + 0.5) / f_ - cx, dy = (Y + 0.5) / f_ - cy;
                const double d2 = (dx * dx + dy * dy) / (radius_ * radius_);
                if (d2 > 4.0) continue;
                const double w = std::exp(-d2);
                sum += w * glm::dvec3(sub.at(X, Y));
                weights += w;
            }
        }
        // A radius far below a sub-pixel leaves no weight: the box is its limit.
        return weights > 0.0 ? glm::vec3(sum / weights) : box(sub, x, y);
    }

    glm::vec3 box(const ImageRGB& sub, int x, int y) const {
        glm::dvec3 sum(0.0);
        for (int j = 0; j < f_; ++j)
            for (int i = 0; i < f_; ++i) sum += glm::dvec3(sub.at(x * f_ + i, y * f_ + j));
        return glm::vec3(sum / static_cast<double>(f_ * f_));
    }

    int n_, f_;
    DownFilter filter_;
    double radius_;
};

}  // namespace

StrategyDescriptor supersampleStrategy() {
    StrategyDescriptor d;
    d.name = "supersample";
    d.doc = "supersample and filter down (pfilt)";
    d.params = {intParam("supersample", 1, 4, 2, "render at this factor of the resolution (1: uniform sampling)"),
                choiceParam("filter", {toString(DownFilter::Box), toString(DownFilter::Gaussian)},
                            "down filter, as pfilt"),
                realParam("filter_radius", 0.01, 10, 0.6, "gaussian: radius in output pixels")};
    d.create = [](const StrategyParams& p, const StrategyInputs& in) {
        const DownFilter filter =
            p.choice("filter") == toString(DownFilter::Gaussian) ? DownFilter::Gaussian : DownFilter::Box;
        return std::make_unique<SupersampleStrategy>(in.strata, p.integer("supersample"), filter,
                                                     p.real("filter_radius"));
    };
    return d;
}

}  // namespace aamap
