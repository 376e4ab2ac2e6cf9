#include "eval/metrics/pixel_error.h"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include "core/image_io.h"

namespace aamap::metrics {
namespace {

void checkSameSize(const ImageRGB& a, const ImageRGB& b) {
    if (a.empty() || b.empty())
        throw std::invalid_argument("pixel error: empty image");
    if (a.width() != b.width() || a.height() != b.height())
        throw std::invalid_argument(fmt::format("pixel error: sizes differ ({}x{} vs {}x{})", a.width(),
                                                a.height(), b.width(), b.height()));
}

float toSpace(float v, const PixelErrorOptions& o) {
    if (o.space == ErrorSpace::Display) return displayEncode(v, o.exposure);
    return std::isfinite(v) ? v : 0.0f;
}

// Mean over channels of the squared difference of one pixel, in double.
double pixelSquaredError(const glm::vec3& r, const glm::vec3& t, const PixelErrorOptions& o) {
    double sum = 0.0;
    for (int k = 0; k < 3; ++k) {
        const double d = double(toSpace(r[k], o)) - double(toSpace(t[k], o));
        sum += d * d;
    }
    return sum / 3.0;
}

}  // namespace

double psnrFromMse(double mse, double peak) {
    if (mse <= 0.0) return std::numeric_limits<double>::infinity();
    return 10.0 * std::log10(peak * peak / mse);
}

ImageGrey squaredErrorMap(const ImageRGB& reference, const ImageRGB& test, const PixelErrorOptions& options) {
    checkSameSize(reference, test);
    ImageGrey map(reference.width(), reference.height());
    tbb::parallel_for(0, reference.height(), [&](int y) {
        for (int x = 0; x < reference.width(); ++x)
            map.at(x, y) = float(pixelSquaredError(reference.at(x, y), test.at(x, y), options));
    });
    return map;
}

PixelError pixelError(const ImageRGB& reference, const ImageRGB& test, const PixelErrorOptions& options) {
    checkSameSize(reference, test);
    const int w = reference.width();
    const int h = reference.height();
    // Per-row partial results, combined in row order: deterministic for any thread count.
    std::vector<double> rowSum(h, 0.0);
    std::vector<std::size_t> rowCount(h, 0);
    tbb::parallel_for(0, h, [&](int y) {
        double sum = 0.0;
        std::size_t count = 0;
        for (int x = 0; x < w; ++x) {
            const double e = pixelSquaredError(reference.at(x, y), test.at(x, y), options);
            sum += e;
            count += e >= options.errorThreshold ? 1 : 0;
        }
        rowSum[y] = sum;
        rowCount[y] = count;
    });
    PixelError out;
    double total = 0.0;
    for (int y = 0; y < h; ++y) {
        total += rowSum[y];
        out.pixelsInError += rowCount[y];
    }
    const double n = double(reference.size());
    out.mse = total / n;
    out.rmse = std::sqrt(out.mse);
    out.psnr = psnrFromMse(out.mse, options.peak);
    out.fractionInError = double(out.pixelsInError) / n;
    return out;
}

PixelError pixelErrorDisplay(const ImageRGB& reference, const ImageRGB& test, float exposure) {
    PixelErrorOptions o;
    o.space = ErrorSpace::Display;
    o.exposure = exposure;
    return pixelError(reference, test, o);
}

PixelError pixelErrorLinear(const ImageRGB& reference, const ImageRGB& test) {
    PixelErrorOptions o;
    o.space = ErrorSpace::Linear;
    return pixelError(reference, test, o);
}

}  // namespace aamap::metrics
