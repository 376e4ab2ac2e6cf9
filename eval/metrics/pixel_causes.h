#pragma once
// Why a pixel is in error, or why rays were spent on it for nothing: the instrument for improving
// the aamap (docs/experiments.md, "Causes"). Each pixel gets one cause from the tracer's pixel
// facts (core/pixel_facts.h), by a fixed priority: the first that holds of
//   beside an error (missed pixels only: the pixel's own display value equals the reference's;
//   FLIP rose there from a neighbour's error, and no ray at this pixel can change it),
//   interpolated (the render shot no ray there: a Space block filled it in), emitter, glass,
//   planar mirror, curved mirror, silhouette, shadow boundary, penumbra, texture, highlight,
//   crease, other.
// Two pixel sets are explained:
//   missed  = error pixels: FLIP(image, reference) > threshold;
//   wasted  = pixels given more than one primary ray where one was enough:
//             FLIP(1-ray image, reference) <= threshold.
// For the aamap itself: missed = true aliasing the map did not flag, wasted = flagged pixels that
// are not truly aliased.
#include <array>
#include <cstdint>
#include <string>

#include "core/image.h"
#include "core/image_io.h"
#include "core/pixel_facts.h"

namespace aamap::metrics {

enum class PixelCause : std::uint8_t {
    BesideError,
    Interpolated,
    Emitter,
    Glass,
    PlanarMirror,
    CurvedMirror,
    Silhouette,
    ShadowBoundary,
    Penumbra,
    Texture,
    Highlight,
    Crease,
    Other,
};
constexpr int kPixelCauses = static_cast<int>(PixelCause::Other) + 1;

const char* toString(PixelCause cause);  // "shadow boundary", ...
const char* key(PixelCause cause);       // "shadow_boundary", ... (JSON keys)
glm::u8vec3 colour(PixelCause cause);    // the cause image's colour (distinct, legend in the report)

PixelCause classify(std::uint16_t facts, bool interpolated);

struct CauseCounts {
    std::array<std::uint64_t, kPixelCauses> missed{}, wasted{};
    std::uint64_t missedTotal() const;
    std::uint64_t wastedTotal() const;
};

// One render: `error` its FLIP map against the reference, `oneRayError` the 1-ray image's,
// `rays` its primary rays per pixel (0: interpolated), `own` (may be null) 1 where the render's own
// display value differs from the reference's (map_quality.h, ownDisplayDifference). Fills `image`
// (if not null) with missed pixels in their cause's colour, wasted ones in a darker shade of it,
// the rest black.
CauseCounts renderCauses(const PixelFacts& facts, const ImageGrey& error, const ImageGrey& oneRayError,
                         const Image<std::uint16_t>& rays, const Image<std::uint8_t>* own, float threshold,
                         ImageRGB8* image);

// The aamap: missed = oneRayError > threshold and aamap == 0; wasted = aamap > 0 and
// oneRayError <= threshold; `own` that of the 1-ray image. `image` as above.
CauseCounts mapCauses(const PixelFacts& facts, const ImageGrey& oneRayError, const ImageGrey& aamap,
                      const Image<std::uint8_t>* own, float threshold, ImageRGB8* image);

}  // namespace aamap::metrics
