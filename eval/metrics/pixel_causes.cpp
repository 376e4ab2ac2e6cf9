#include "eval/metrics/pixel_causes.h"

#include <numeric>
#include <stdexcept>

#include <fmt/format.h>

namespace aamap::metrics {
namespace {

using namespace pixel_fact;

struct CauseInfo {
    const char* name;
    const char* key;
    glm::u8vec3 colour;
};

// In PixelCause order. Colours: distinct hues, readable on black.
constexpr std::array<CauseInfo, kPixelCauses> kCauses = {{
    {"beside an error", "beside_error", {90, 70, 60}},
    {"interpolated", "interpolated", {255, 255, 255}},
    {"emitter", "emitter", {255, 230, 0}},
    {"glass", "glass", {0, 220, 255}},
    {"planar mirror", "planar_mirror", {60, 120, 255}},
    {"curved mirror", "curved_mirror", {170, 90, 255}},
    {"silhouette", "silhouette", {255, 60, 60}},
    {"shadow boundary", "shadow_boundary", {0, 200, 80}},
    {"penumbra", "penumbra", {150, 255, 120}},
    {"texture", "texture", {255, 140, 0}},
    {"highlight", "highlight", {255, 120, 200}},
    {"crease", "crease", {200, 120, 60}},
    {"other", "other", {128, 128, 128}},
}};

void requireSizes(const PixelFacts& facts, int w, int h, const char* what) {
    if (facts.width() != w || facts.height() != h)
        throw std::invalid_argument(fmt::format("pixel facts are {}x{}, the {} is {}x{}", facts.width(), facts.height(),
                                                what, w, h));
}

glm::u8vec3 darker(glm::u8vec3 c) { return {static_cast<std::uint8_t>(c.r / 3), static_cast<std::uint8_t>(c.g / 3),
                                            static_cast<std::uint8_t>(c.b / 3)}; }

// Counts and paints one pixel set of each kind.
template <class Missed, class Wasted>
CauseCounts countCauses(const PixelFacts& facts, Missed&& missed, Wasted&& wasted, ImageRGB8* image,
                        const Image<std::uint16_t>* rays, const Image<std::uint8_t>* own) {
    CauseCounts counts;
    if (image) *image = ImageRGB8(facts.width(), facts.height());
    for (int y = 0; y < facts.height(); ++y)
        for (int x = 0; x < facts.width(); ++x) {
            const bool isMissed = missed(x, y), isWasted = !isMissed && wasted(x, y);
            if (!isMissed && !isWasted) continue;
            const PixelCause cause = isMissed && own != nullptr && own->at(x, y) == 0
                                         ? PixelCause::BesideError
                                         : classify(facts.at(x, y), rays != nullptr && rays->at(x, y) == 0);
            const auto i = static_cast<std::size_t>(cause);
            (isMissed ? counts.missed : counts.wasted)[i] += 1;
            if (image) image->at(x, y) = isMissed ? kCauses[i].colour : darker(kCauses[i].colour);
        }
    return counts;
}

}  // namespace

const char* toString(PixelCause cause) { return kCauses[static_cast<std::size_t>(cause)].name; }
const char* key(PixelCause cause) { return kCauses[static_cast<std::size_t>(cause)].key; }
glm::u8vec3 colour(PixelCause cause) { return kCauses[static_cast<std::size_t>(cause)].colour; }

PixelCause classify(std::uint16_t f, bool interpolated) {
    // Interpolated first: whatever the pixel shows, no ray looked at it. Then what the Snapshot
    // models least well, down to what it sees directly.
    if (interpolated) return PixelCause::Interpolated;
    if (f & Emitter) return PixelCause::Emitter;
    if (f & Glass) return PixelCause::Glass;
    if (f & PlanarMirror) return PixelCause::PlanarMirror;
    if (f & CurvedMirror) return PixelCause::CurvedMirror;
    if (f & Silhouette) return PixelCause::Silhouette;
    if (f & ShadowBoundary) return PixelCause::ShadowBoundary;
    if (f & Penumbra) return PixelCause::Penumbra;
    if (f & pixel_fact::Texture) return PixelCause::Texture;
    if (f & Glossy) return PixelCause::Highlight;
    if (f & Crease) return PixelCause::Crease;
    return PixelCause::Other;
}

std::uint64_t CauseCounts::missedTotal() const { return std::accumulate(missed.begin(), missed.end(), std::uint64_t{0}); }
std::uint64_t CauseCounts::wastedTotal() const { return std::accumulate(wasted.begin(), wasted.end(), std::uint64_t{0}); }

CauseCounts renderCauses(const PixelFacts& facts, const ImageGrey& error, const ImageGrey& oneRayError,
                         const Image<std::uint16_t>& rays, const Image<std::uint8_t>* own, float threshold,
                         ImageRGB8* image) {
    requireSizes(facts, error.width(), error.height(), "error map");
    if (own) requireSizes(facts, own->width(), own->height(), "own-difference mask");
    requireSizes(facts, oneRayError.width(), oneRayError.height(), "1-ray error map");
    requireSizes(facts, rays.width(), rays.height(), "rays-per-pixel image");
    return countCauses(
        facts, [&](int x, int y) { return error.at(x, y) > threshold; },
        [&](int x, int y) { return rays.at(x, y) > 1 && oneRayError.at(x, y) <= threshold; }, image, &rays, own);
}

CauseCounts mapCauses(const PixelFacts& facts, const ImageGrey& oneRayError, const ImageGrey& aamap,
                      const Image<std::uint8_t>* own, float threshold, ImageRGB8* image) {
    if (own) requireSizes(facts, own->width(), own->height(), "own-difference mask");
    requireSizes(facts, oneRayError.width(), oneRayError.height(), "1-ray error map");
    requireSizes(facts, aamap.width(), aamap.height(), "aamap");
    return countCauses(
        facts, [&](int x, int y) { return oneRayError.at(x, y) > threshold && !(aamap.at(x, y) > 0.0f); },
        [&](int x, int y) { return aamap.at(x, y) > 0.0f && oneRayError.at(x, y) <= threshold; }, image, nullptr, own);
}

}  // namespace aamap::metrics
