#pragma once
// What one view of the scene needs from the Snapshot's raster, decided on the CPU before the graph
// runs (no Vulkan): the region it can see, how many point samples each area light needs there,
// and which triangles can reach its pixels, directly or by their shadows.
//
// * The visible region: the view frustum's bounding box clipped to the scene's bounds.
// * Area-light samples by need: a light's samples exist to resolve how its extent changes the
//   shading and the shadows across the region; the soft-shadow filter (glsl/shadow_visibility.glsl)
//   spreads each sample's shadow over its patch's penumbra. So a light gets one sample per
//   `solidAnglePerSample` steradians of its mean solid angle over the visible region (at least 1,
//   at most the configured count): a small or far light one, a large near one the configured count.
// * View culling: the camera's draws take only triangles not entirely outside one of the
//   frustum's side planes or behind the eye, and a shadow face only the triangles that can lie
//   between its light and some point in view: for each of those planes with the light (and the
//   patch it stands for) inside it, a triangle entirely outside cannot cut a segment from the
//   light to a point inside (both ends lie in the half-space, and so does the segment).
// * Shadow-map resolution by need: a shadow edge drawn from a map moves by up to one texel's
//   footprint at its receiver; the Laplacian sees that move as the edge's contrast times its
//   distance. So each light's cube faces get the fewest texels for which a texel at every sampled
//   receiver in view spans at most `texelPixels / c` pixels of the map, c the light's share of the
//   unshadowed irradiance there: a light near what it lights, far from the eye, or outshone by
//   another gets fewer texels.
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "scene/lights.h"

namespace aamap::passes {

// The view frustum's side planes and the eye plane, inward (dot(xyz, p) + w >= 0 inside), xyz of
// unit length, from a view-projection matrix (clip x, y in [-w, w], w > 0 in front of the eye;
// the depth convention does not matter). margin widens the sides by that share of the frustum's
// half-extent, so a filter tap just beyond the border still finds its occluders.
struct ViewFrustum {
    std::array<glm::vec4, 5> planes{};  // left, right, bottom, top, eye
    static ViewFrustum fromViewProjection(const glm::mat4& viewProj, float margin = 0.02f);
    // True when all three points lie outside one plane.
    bool triangleOutside(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) const;
    bool operator==(const ViewFrustum&) const = default;
};

// The bounding box of the frustum's part within `scene` (corners at clip depths 0 and 1 of the
// matrix, which for the Snapshot's camera enclose the scene's bounding sphere), clipped to it.
Bounds visibleRegion(const glm::mat4& viewProj, const Bounds& scene);

// The mean, over a 3 x 3 x 3 lattice of points spanning `region`, of the solid angle a planar
// one-sided light of `area` at `centre` facing `normal` subtends there: area * cos / d^2, with
// cos the emitter's (0 behind it; 1 everywhere when normal is zero) and d^2 at least area (the
// light seen from nearer than its own size counts as 1 sr, whatever the distance).
double meanSolidAngle(double area, const glm::vec3& centre, const glm::vec3& normal, const Bounds& region);

// ceil(solidAngle / solidAnglePerSample) in [1, maxSamples]; solidAnglePerSample <= 0: maxSamples.
int areaLightSamplesFor(double solidAngle, double solidAnglePerSample, int maxSamples);

// The triangles (three consecutive positions each, of the first `triangles`) the frustum keeps.
std::vector<std::uint32_t> trianglesInView(std::span<const glm::vec3> positions, std::uint32_t triangles,
                                           const ViewFrustum& frustum);

// Of a face list (index triples into `positions`), the triangles that can shadow a point in view
// from a light at `light` standing for a patch within `patchRadius` of it: planes with the light
// at least patchRadius inside them cull the triangles entirely outside. Appends to `out`.
void cullShadowCasters(std::span<const glm::vec3> positions, std::span<const std::uint32_t> faceIndices,
                       const glm::vec3& light, float patchRadius, const ViewFrustum& frustum,
                       std::vector<std::uint32_t>& out);

// The least and the rounding step of a shadow cube face's side chosen by need (texels), below the
// configured resolution: a face's side is a multiple of the step, so small view changes rarely
// change it (the lit shaders inline the sizes).
inline constexpr int kMinShadowFaceSize = 32;
inline constexpr int kShadowFaceStep = 16;

// What shadowFaceSizes needs of the view: its camera and raster, and the region it can see.
struct ShadowNeedView {
    glm::mat4 viewProj{1.0f};  // the Snapshot camera's (clip x, y in [-w, w], w the eye's depth)
    glm::vec3 eye{0.0f};
    glm::uvec2 pixels{0u};     // the map's size (the render's): the pixels an edge must be placed in
    Bounds region;             // visibleRegion(viewProj, scene bounds)
};

// The receivers shadowFaceSizes samples: along a 5 x 5 grid of the camera's rays, the points at a
// quarter, half, three quarters and all of each ray's segment inside `region` (from the eye when
// it is inside). Rays that miss the region add none.
std::vector<glm::vec3> shadowReceivers(const ShadowNeedView& view);

// Texels per cube-face side for each light (a multiple of kShadowFaceStep in [min(kMinShadowFaceSize,
// maxSize), maxSize]): the least for which, at every receiver p of shadowReceivers, the face's
// texel there (at most 2 d / size wide at distance d from the light) spans at most
// texelPixels / c(p) pixels of the raster, c(p) = E_i(p) / (sum_j E_j(p) + otherIrradiance) with
// E_j = luminance(intensity) x emission factor / d^2 (the unshadowed irradiance, the receiver's
// cosine left out). otherIrradiance: what lights at infinity add (luminance). texelPixels <= 0:
// every light maxSize.
std::vector<int> shadowFaceSizes(std::span<const PointLight> lights, double otherIrradiance, const ShadowNeedView& view,
                                 float texelPixels, int maxSize);

}  // namespace aamap::passes
