#include "eval/metrics/map_quality.h"

#include <stdexcept>

#include <fmt/format.h>

#include "core/image_io.h"

namespace aamap::metrics {

Image<std::uint8_t> ownDisplayDifference(const ImageRGB& a, const ImageRGB& b, float exposure) {
    if (a.width() != b.width() || a.height() != b.height())
        throw std::invalid_argument(fmt::format("map quality: images are {}x{} and {}x{}", a.width(), a.height(),
                                                b.width(), b.height()));
    const ImageRGB8 da = toneMap(a, exposure), db = toneMap(b, exposure);
    Image<std::uint8_t> differs(a.width(), a.height(), 0);
    for (std::size_t i = 0; i < differs.size(); ++i) differs.pixels()[i] = da.pixels()[i] != db.pixels()[i] ? 1 : 0;
    return differs;
}

MapQuality mapQuality(const ImageGrey& flipError, const ImageGrey& aamap, float aliasingThreshold,
                      const Image<std::uint8_t>* ownDiffers) {
    if (flipError.empty() || aamap.empty()) throw std::invalid_argument("map quality: empty image");
    if (flipError.width() != aamap.width() || flipError.height() != aamap.height())
        throw std::invalid_argument(fmt::format("map quality: FLIP map is {}x{} but the aamap is {}x{}",
                                                flipError.width(), flipError.height(), aamap.width(),
                                                aamap.height()));
    if (ownDiffers && (ownDiffers->width() != aamap.width() || ownDiffers->height() != aamap.height()))
        throw std::invalid_argument(fmt::format("map quality: own-difference mask is {}x{} but the aamap is {}x{}",
                                                ownDiffers->width(), ownDiffers->height(), aamap.width(),
                                                aamap.height()));
    MapQuality q;
    q.pixels = flipError.size();
    for (std::size_t i = 0; i < q.pixels; ++i) {
        const bool isTrue = flipError.pixels()[i] > aliasingThreshold;
        const bool ownTrue = isTrue && (!ownDiffers || ownDiffers->pixels()[i] != 0);
        const bool flagged = aamap.pixels()[i] > 0.0f;
        q.truePixels += isTrue ? 1 : 0;
        q.flaggedPixels += flagged ? 1 : 0;
        q.truePositives += (isTrue && flagged) ? 1 : 0;
        q.ownTruePixels += ownTrue ? 1 : 0;
        q.ownTruePositives += (ownTrue && flagged) ? 1 : 0;
    }
    q.recall = q.truePixels == 0 ? 1.0 : double(q.truePositives) / double(q.truePixels);
    q.ownRecall = q.ownTruePixels == 0 ? 1.0 : double(q.ownTruePositives) / double(q.ownTruePixels);
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
    const Image<std::uint8_t> own = ownDisplayDifference(oneRay, reference, options.exposure);
    return mapQuality(flip.errorMap, aamap, options.aliasingThreshold, &own);
}

}  // namespace aamap::metrics
