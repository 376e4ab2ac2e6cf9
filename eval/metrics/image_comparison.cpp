#include "eval/metrics/image_comparison.h"

namespace aamap::metrics {

Comparison compareImages(const ImageRGB& reference, const ImageRGB& test, const ComparisonOptions& options) {
    PixelErrorOptions po;
    po.exposure = options.exposure;
    po.errorThreshold = options.mseThreshold;
    FlipOptions fo;
    fo.ppd = options.ppd;
    fo.threshold = options.flipThreshold;
    Comparison c;
    c.display = pixelError(reference, test, po);
    if (options.flip) c.flip = flipDisplay(reference, test, options.exposure, fo);
    if (options.flipHdr) c.flipHdr = flipHdr(reference, test, fo);
    return c;
}

}  // namespace aamap::metrics
