#include "eval/evaluate.h"

#include <algorithm>
#include <cmath>

#include <glm/common.hpp>

#include "eval/metrics/flip.h"
#include "eval/metrics/image_comparison.h"
#include "eval/metrics/magma.h"
#include "eval/metrics/map_quality.h"
#include "eval/metrics/pixel_causes.h"
#include "eval/metrics/worst_regions.h"
#include "eval/metrics/pixel_error.h"

namespace aamap {
namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

namespace {

metrics::FlipOptions flipOptions(const MetricsConfig& m) {
    metrics::FlipOptions o;
    o.ppd = static_cast<float>(m.ppd);
    o.threshold = static_cast<float>(m.flipThreshold);
    return o;
}

metrics::ComparisonOptions comparisonOptions(const MetricsConfig& m, float exposure) {
    metrics::ComparisonOptions o;
    o.exposure = exposure;
    o.ppd = static_cast<float>(m.ppd);
    o.flipThreshold = static_cast<float>(m.flipThreshold);
    o.mseThreshold = m.mseThreshold;
    o.flip = m.flip;
    o.flipHdr = m.flipHdr;
    return o;
}

Json finiteOrNull(double v) { return std::isfinite(v) ? Json(v) : Json(nullptr); }

Json causesJson(const metrics::CauseCounts& c, const std::string& image) {
    Json missed = Json::object(), wasted = Json::object();
    for (int i = 0; i < metrics::kPixelCauses; ++i) {
        const auto cause = static_cast<metrics::PixelCause>(i);
        missed[metrics::key(cause)] = c.missed[static_cast<std::size_t>(i)];
        wasted[metrics::key(cause)] = c.wasted[static_cast<std::size_t>(i)];
    }
    return {{"missed", missed}, {"wasted", wasted}, {"missed_total", c.missedTotal()},
            {"wasted_total", c.wastedTotal()}, {"image", image}};
}

}  // namespace

ImageRGB8 errorOverlay(const ImageRGB8& base, const ImageGrey& error, float threshold) {
    ImageRGB8 out(base.width(), base.height());
    for (int y = 0; y < base.height(); ++y)
        for (int x = 0; x < base.width(); ++x) {
            const glm::u8vec3 c = base.at(x, y);
            // Grey base so the red reads on any colour; 0.7 keeps the image recognisable.
            const float grey = 0.7f * (0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b);
            const float a = std::clamp(error.at(x, y) / (2.0f * threshold), 0.0f, 1.0f);
            const auto mix = [&](float target) { return static_cast<std::uint8_t>(std::lround(grey + a * (target - grey))); };
            out.at(x, y) = {mix(255.0f), mix(0.0f), mix(0.0f)};
        }
    return out;
}

Json evaluateRender(const ImageRGB& reference, const ImageRGB& test, const MetricsConfig& m, float exposure,
                    const fs::path& outDir, const std::string& name, std::vector<std::string>& outputs,
                    ImageGrey* flipError) {
    const metrics::Comparison c = metrics::compareImages(reference, test, comparisonOptions(m, exposure));
    if (flipError) *flipError = c.flip ? c.flip->errorMap : ImageGrey();
    Json j;
    j["mse"] = c.display.mse;
    j["rmse"] = c.display.rmse;
    j["psnr"] = finiteOrNull(c.display.psnr);
    j["pct_error_mse"] = 100.0 * c.display.fractionInError;
    if (c.flip) {
        j["flip_mean"] = c.flip->mean;
        j["pct_error_flip"] = 100.0 * c.flip->fractionAbove;
        // The report's crops: where to look first. Computed here, where the float map exists.
        Json regions = Json::array();
        const ImageGrey& e = c.flip->errorMap;
        for (const metrics::Region& r : metrics::worstRegions(e, metrics::defaultRegionSize(e.width(), e.height()), 4))
            regions.push_back({{"x", r.x}, {"y", r.y}, {"size", r.size}, {"flip_mean", r.meanError}});
        j["worst_regions"] = regions;
        writePng(outDir / (name + ".flip.png"), toneMap(metrics::flipMagma(*c.flip), 1.0f));
        writePng(outDir / (name + ".overlay.png"),
                 errorOverlay(toneMap(test, exposure), c.flip->errorMap, static_cast<float>(m.flipThreshold)));
        outputs.push_back(name + ".flip.png");
        outputs.push_back(name + ".overlay.png");
    }
    if (c.flipHdr) {
        j["flip_hdr_mean"] = c.flipHdr->mean;
        j["pct_error_flip_hdr"] = 100.0 * c.flipHdr->fractionAbove;
        writePng(outDir / (name + ".flip_hdr.png"), toneMap(metrics::flipMagma(*c.flipHdr), 1.0f));
        outputs.push_back(name + ".flip_hdr.png");
    }
    return j;
}

OracleMap oracleMap(const ImageRGB& oneRay, const ImageRGB& reference, const MetricsConfig& m, float exposure,
                    int maxRounds) {
    const float t = static_cast<float>(m.flipThreshold);
    OracleMap o{ImageGrey(oneRay.width(), oneRay.height(), 0.0f), 0, 0};
    ImageRGB composite = oneRay;
    for (o.rounds = 1; o.rounds <= maxRounds; ++o.rounds) {
        const metrics::FlipResult f = metrics::flipDisplay(reference, composite, exposure, flipOptions(m));
        o.residualErrorPercent = 100.0 * f.fractionAbove;
        bool grew = false;
        for (std::size_t i = 0; i < f.errorMap.size(); ++i)
            if (f.errorMap.pixels()[i] > t && o.map.pixels()[i] == 0.0f) {
                o.map.pixels()[i] = 1.0f;
                composite.pixels()[i] = reference.pixels()[i];
                grew = true;
            }
        if (!grew) break;
    }
    o.rounds = std::min(o.rounds, maxRounds);
    return o;
}

Json evaluateMap(const ImageRGB& oneRay, const ImageRGB& reference, const ImageGrey& aamap, const MetricsConfig& m,
                 float exposure, const fs::path& outDir, ImageGrey* oneRayError) {
    const float t = static_cast<float>(m.flipThreshold);
    const metrics::FlipResult f = metrics::flipDisplay(reference, oneRay, exposure, flipOptions(m));
    if (oneRayError) *oneRayError = f.errorMap;
    const Image<std::uint8_t> own = metrics::ownDisplayDifference(oneRay, reference, exposure);
    const metrics::MapQuality q = metrics::mapQuality(f.errorMap, aamap, t, &own);
    const ImageRGB8 base = toneMap(oneRay, exposure);
    ImageRGB8 img(base.width(), base.height());
    for (int y = 0; y < img.height(); ++y)
        for (int x = 0; x < img.width(); ++x) {
            const bool truth = f.errorMap.at(x, y) > t, flagged = aamap.at(x, y) > 0.0f;
            const glm::u8vec3 c = base.at(x, y);
            // Misses whose own pixel equals the reference's (FLIP spread from a neighbour) in orange.
            img.at(x, y) = truth && flagged ? glm::u8vec3(255, 255, 255)
                           : truth          ? (own.at(x, y) ? glm::u8vec3(255, 0, 0) : glm::u8vec3(255, 160, 0))
                           : flagged        ? glm::u8vec3(40, 90, 255)
                                            : glm::u8vec3(c.r / 3, c.g / 3, c.b / 3);
        }
    writePng(outDir / "aliasing.png", img);
    return {{"threshold", t},
            {"pixels", q.pixels},
            {"true_pixels", q.truePixels},
            {"flagged_pixels", q.flaggedPixels},
            {"true_positives", q.truePositives},
            {"recall", q.recall},
            {"precision", q.precision},
            {"flagged_fraction", q.flaggedFraction},
            {"true_fraction", q.trueFraction},
            {"own_true_pixels", q.ownTruePixels},
            {"own_true_positives", q.ownTruePositives},
            {"own_recall", q.ownRecall},
            {"image", "aliasing.png"}};
}

Json evaluateAgainstRender(const std::string& againstName, const ImageRGB& against, const ImageRGB& test,
                           const MetricsConfig& m, float exposure) {
    const metrics::Comparison c = metrics::compareImages(against, test, comparisonOptions(m, exposure));
    Json j;
    j["against"] = againstName;
    j["mse"] = c.display.mse;
    j["pct_error_mse"] = 100.0 * c.display.fractionInError;
    if (c.flip) {
        j["flip_mean"] = c.flip->mean;
        j["pct_error_flip"] = 100.0 * c.flip->fractionAbove;
    }
    return j;
}

Json estimateReferenceNoise(const ImageRGB& reference, const ImageRGB& halfDifference, int rpp, const MetricsConfig& m,
                            float exposure) {
    const metrics::ComparisonOptions options = comparisonOptions(m, exposure);
    // The floor a reference of `rays` rays per pixel would have: its noise scales as 1/sqrt(rays).
    const auto floorAt = [&](int rays, Json* out) {
        const float scale = 0.5f * std::sqrt(static_cast<float>(rpp) / static_cast<float>(rays));
        ImageRGB noisy(reference.width(), reference.height());
        for (std::size_t i = 0; i < noisy.size(); ++i)
            noisy.pixels()[i] = glm::max(reference.pixels()[i] + scale * halfDifference.pixels()[i], glm::vec3(0.0f));
        const metrics::Comparison c = metrics::compareImages(reference, noisy, options);
        if (out != nullptr) {
            (*out)["mse"] = c.display.mse;
            (*out)["pct_error_mse"] = 100.0 * c.display.fractionInError;
            if (c.flip) {
                (*out)["flip_mean"] = c.flip->mean;
                (*out)["pct_error_flip"] = 100.0 * c.flip->fractionAbove;
            }
        }
        return 100.0 * (c.flip ? c.flip->fractionAbove : c.display.fractionInError);
    };
    Json j;
    j["method"] = "two half images (strata of even and odd x + y)";
    j["rpp"] = rpp;
    const double floor = floorAt(rpp, &j);
    j["floor_pct"] = floor;
    j["converged"] = floor <= kConvergedFloorPercent;
    j["noisy"] = floor > kNoisyFloorPercent;
    Json suggested = nullptr;
    if (floor <= kConvergedFloorPercent) {
        suggested = rpp;
    } else {  // the floor falls as rays grow: bisect over n for n x n rays
        int lo = static_cast<int>(std::sqrt(static_cast<double>(rpp))), hi = 64;
        if (floorAt(hi * hi, nullptr) <= kConvergedFloorPercent) {
            while (hi - lo > 1) {
                const int mid = (lo + hi) / 2;
                (floorAt(mid * mid, nullptr) <= kConvergedFloorPercent ? hi : lo) = mid;
            }
            suggested = hi * hi;
        }
    }
    j["suggested_rpp"] = suggested;
    return j;
}

Json evaluateRenderCauses(const PixelFacts& facts, const ImageRGB& reference, const ImageRGB& test, float exposure,
                          const ImageGrey& flipError, const ImageGrey& oneRayError, const Image<std::uint16_t>& rays,
                          float threshold, const fs::path& outDir, const std::string& name,
                          std::vector<std::string>& outputs) {
    ImageRGB8 image;
    const Image<std::uint8_t> own = metrics::ownDisplayDifference(test, reference, exposure);
    const metrics::CauseCounts c = metrics::renderCauses(facts, flipError, oneRayError, rays, &own, threshold, &image);
    const std::string file = name + ".causes.png";
    writePng(outDir / file, image);
    outputs.push_back(file);
    return causesJson(c, file);
}

Json evaluateMapCauses(const PixelFacts& facts, const ImageRGB& reference, const ImageRGB& oneRay, float exposure,
                       const ImageGrey& oneRayError, const ImageGrey& aamap, float threshold, const fs::path& outDir) {
    ImageRGB8 image;
    const Image<std::uint8_t> own = metrics::ownDisplayDifference(oneRay, reference, exposure);
    const metrics::CauseCounts c = metrics::mapCauses(facts, oneRayError, aamap, &own, threshold, &image);
    writePng(outDir / "causes.png", image);
    return causesJson(c, "causes.png");
}

}  // namespace aamap
