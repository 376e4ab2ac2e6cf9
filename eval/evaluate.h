#pragma once
// Metrics of one render against the reference, and of the aamap against true aliasing, with their
// images (FLIP error maps, the paper's Figure 8 red overlay, the aliasing classification).
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/image.h"
#include "core/image_io.h"
#include "core/pixel_facts.h"
#include "eval/config.h"

namespace aamap {

// {mse, rmse, psnr, pct_error_mse, flip_mean, pct_error_flip, worst_regions[, flip_hdr_mean,
// pct_error_flip_hdr]}; worst_regions: up to 4 non-overlapping square windows [{x, y, size,
// flip_mean}] with the largest summed FLIP error, worst first (eval/metrics/worst_regions.h).
// MSE-family values are in display space (what the PNGs show, eval/metrics/pixel_error.h); psnr
// is null for identical images. Writes NAME.flip.png (magma) and NAME.overlay.png (FLIP error in
// red over the render, Figure 8) into outDir when FLIP is on, and appends their names to outputs.
// flipError (if not null) receives the LDR-FLIP error map (empty when FLIP is off).
nlohmann::ordered_json evaluateRender(const ImageRGB& reference, const ImageRGB& test, const MetricsConfig& metrics,
                                      float exposure, const std::filesystem::path& outDir, const std::string& name,
                                      std::vector<std::string>& outputs, ImageGrey* flipError = nullptr);

// The error of `test` against another render of the same shading mode (no files written):
// {against, mse, pct_error_mse, flip_mean, pct_error_flip} (the FLIP fields when FLIP is on).
// Against the most-sampled uniform render of the mode, it is the antialiasing share of the error,
// apart from the mode's shading bias (docs/experiments.md, "Error against ground truth").
nlohmann::ordered_json evaluateAgainstRender(const std::string& againstName, const ImageRGB& against,
                                             const ImageRGB& test, const MetricsConfig& metrics, float exposure);

// How converged a traced reference is, from the difference D of two independent half images of
// its samples (TraceResult::halfDifference). D / 2 has the spread of the whole reference's own
// error (noise and antialiasing left), so the reference against reference + D / 2 gives the error
// pixels its noise alone makes: the floor under every error figure measured against it.
// {method, rpp, pct_error_flip, flip_mean (FLIP on), pct_error_mse, mse, floor_pct (the FLIP
// figure, else the MSE one), converged (floor_pct <= kConvergedFloorPercent), noisy (floor_pct >
// kNoisyFloorPercent), suggested_rpp (the
// smallest square rpp, up to kMaxSuggestedRpp, whose noise, scaled as 1 / sqrt(rpp), meets that;
// null past it)}.
// Converged: its noise puts at most 1 pixel in 1000 in error. Noisy: more than 1 in 100, where
// the noise, not the renders, decides the error figures (the report leaves them out). Between
// the two, renders that share the reference's samples (the same seed and strata) still compare
// with it, which is the paper's comparison; the report shows the floor beside them.
inline constexpr double kConvergedFloorPercent = 0.1;
inline constexpr double kNoisyFloorPercent = 1.0;
inline constexpr int kMaxSuggestedRpp = 64 * 64;
nlohmann::ordered_json estimateReferenceNoise(const ImageRGB& reference, const ImageRGB& halfDifference, int rpp,
                                              const MetricsConfig& metrics, float exposure);

// Map quality: true aliasing T = FLIP(oneRay vs reference) > flip_threshold, flagged F = aamap > 0.
// {threshold, pixels, true_pixels, flagged_pixels, true_positives, recall, precision,
// flagged_fraction, true_fraction}. Writes aliasing.png: true positives white, misses red (orange
// where the pixel's own display value equals the reference's), false alarms blue, the rest the
// dimmed 1-ray image.
// oneRayError (if not null) receives the 1-ray image's LDR-FLIP error map.
nlohmann::ordered_json evaluateMap(const ImageRGB& oneRay, const ImageRGB& reference, const ImageGrey& aamap,
                                   const MetricsConfig& metrics, float exposure, const std::filesystem::path& outDir,
                                   ImageGrey* oneRayError = nullptr);

// The oracle map (metrics.oracle): 1 where a pixel needs more than one ray by the reference's own
// account, 0 elsewhere. It starts from true aliasing (1-ray FLIP above flip_threshold) and grows
// to a fixed point: the image that takes the reference where the map is 1 and the 1-ray image
// elsewhere (what a render with the reference's budget on the map's pixels gives: sampling is
// deterministic) is measured again, and its error pixels join the map. FLIP compares
// neighbourhoods, so correcting a pixel can uncover an error beside it that wrong neighbours had
// masked. Stops when nothing joins or after maxRounds.
struct OracleMap {
    ImageGrey map;
    int rounds = 0;                  // measurements made (1: true aliasing was already the fixed point)
    double residualErrorPercent = 0; // % FLIP error pixels of the last composite
};
OracleMap oracleMap(const ImageRGB& oneRay, const ImageRGB& reference, const MetricsConfig& metrics, float exposure,
                    int maxRounds = 16);

// Why a render's error pixels were missed and its extra rays wasted (eval/metrics/pixel_causes.h):
// {missed: {cause: pixels}, wasted: {...}, missed_total, wasted_total, image}. Writes
// NAME.causes.png and appends it to outputs.
nlohmann::ordered_json evaluateRenderCauses(const PixelFacts& facts, const ImageRGB& reference, const ImageRGB& test,
                                            float exposure, const ImageGrey& flipError, const ImageGrey& oneRayError,
                                            const Image<std::uint16_t>& rays, float threshold,
                                            const std::filesystem::path& outDir, const std::string& name,
                                            std::vector<std::string>& outputs);

// The same for the aamap against true aliasing; writes causes.png.
nlohmann::ordered_json evaluateMapCauses(const PixelFacts& facts, const ImageRGB& reference, const ImageRGB& oneRay,
                                         float exposure, const ImageGrey& oneRayError, const ImageGrey& aamap,
                                         float threshold, const std::filesystem::path& outDir);

// The red overlay: the display image greyed, with red mixed in by alpha = min(1, error / (2 t)),
// so an error at the threshold t is a half-strength red.
ImageRGB8 errorOverlay(const ImageRGB8& base, const ImageGrey& error, float threshold);

}  // namespace aamap
