#include "eval/metrics/map_quality.h"

#include <stdexcept>

#include <fmt/format.h>

namespace aamap::metrics {

MapQuality mapQuality(const ImageGrey& flipError, const ImageGrey& aamap, float aliasingThreshold) {
    if (flipError.empty() || aamap.empty()) throw std::invalid_argument("map quality: empty image");
    if (flipError.width() != aamap.width() || flipError.height() != aamap.height())
        throw std::invalid_argument(fmt::format("map quality: FLIP map is {}x{} but the aamap is {}x{}",
                                                flipError.width(), flipError.height(), aamap.width(),
                                                aamap.height()));
    MapQuality q;
    q.pixels = flipError.size();
    for (std::size_t i = 0; i < q.pixels; ++i) {
        const bool isTrue = flipError.pixels()[i] > aliasingThreshold;
        const bool flagged = aamap.pixels()[i] > 0.0f;
        q.truePixels += isTrue ? 1 : 0;
        q.flaggedPixels += flagged ? 1 : 0;
        q.truePositives += (isTrue && flagged) ? 1 : 0;
    }
    q.recall = q.truePixels == 0 ? 1.0 : double(q.truePositives) / double(q.truePixels);
    q.precision = q.flaggedPixels == 0 ? 1.0 : double(q.truePositives) / double(q.flaggedPixels);
    q.flaggedFraction = double(q.flaggedPixels) / double(q.pixels);
    q.trueFraction = double(q.truePixels) / double(q.pixels);
    return q;
}

MapQuality mapQuality(const ImageRGB& oneRay, const ImageRGB& reference, const ImageGrey& aamap,
                      const MapQualityOptions& options) {
    // FLIP takes (reference, test): the converged image is the reference.
    const FlipResult flip = options.range == FlipRange::Hdr
                                ? flipHdr(reference, oneRay, options.flip)
                                : flipDisplay(reference, oneRay, options.exposure, options.flip);
    return mapQuality(flip.errorMap, aamap, options.aliasingThreshold);
}

}  // namespace aamap::metrics
