#pragma once
// Light sources as the integrator samples them. An area light is a set of emissive triangles with
// one radiance; a 2D sample in [0,1)^2 picks a triangle (CDF over the triangles) and reuses the
// rescaled remainder to place a point on it, so a stratified 2D pattern stays stratified over the
// whole light. The point is placed by solid angle as the receiver sees the light (uniform over
// the spherical triangles, tracer/spherical_triangle.h) or uniformly by area; LightView holds
// which, per receiver (docs/tracer.md, "Light sampling").
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "scene/lights.h"
#include "scene/scene.h"
#include "tracer/environment.h"
#include "tracer/spherical_triangle.h"

namespace aamap {

class EmbreeScene;

struct LightPoint {
    glm::vec3 position;
    glm::vec3 normal;  // unit, the emitting side; zero for a failed sample, which cos' = 0 rejects
};

// An area light as one receiver point sees it: how its samples are placed from there.
struct LightView {
    // Lights with at most this many triangles can be sampled by solid angle (one solid angle per
    // triangle per receiver); larger meshes are sampled by area.
    static constexpr int kMaxTriangles = 8;
    // Below this many steradians a light is sampled by area: the angle sums of the spherical
    // sampling lose float precision (pbrt-v4 switches at 3e-4 sr too).
    static constexpr float kMinSolidAngle = 3e-4f;
    // Above this many steradians (the receiver all but touching the light, its triangles close
    // to hemispheres) the solid angles themselves lose float precision: by area again, as
    // pbrt-v4 does from the same 6.22 sr.
    static constexpr float kMaxSolidAngle = 6.22f;
    // A light is sampled by solid angle only where area sampling's density in solid angle varies
    // over it by more than this factor: the near field, where 1/d^2 peaks. Farther out the
    // density is smooth, stratification removes most of its variance, and solid-angle samples
    // would cost more than they save (docs/tracer.md, "Light sampling").
    static constexpr float kMaxDensityRatio = 4.0f;
    // > 0: sampled by solid angle, the sum over the triangles facing the receiver (and so the
    // inverse of every sample's pdf); 0: sampled by area.
    float solidAngle = 0.0f;
    float cdf[kMaxTriangles];    // by solid angle: CDF over the light's triangles (cdf[n - 1] == 1)
    float omega[kMaxTriangles];  // by solid angle: each triangle's, 0 for those facing away
    // Each triangle's sampling setup, made on its first sample (bit i of `ready`).
    SphericalTriangle spherical[kMaxTriangles];
    std::uint32_t ready = 0;
    std::uint32_t degenerate = 0;  // bit i: triangle i's setup failed
};

class AreaLightSampler {
public:
    // Throws std::invalid_argument for triangle indices outside the mesh.
    AreaLightSampler(const AreaLight& light, const EmbreeScene& geometry);

    const glm::vec3& radiance() const { return radiance_; }
    float area() const { return area_; }  // sum of the triangle areas, the 1/pdf of sample()
    // Max |coordinate| of its vertices: float error scale of a sampled point (see ray_offset.h).
    float vertexScale() const { return vertexScale_; }
    bool empty() const { return tris_.empty(); }
    // Bounds for per-hit light selection: every point of the light lies within boundRadius() of
    // centroid(), and every triangle normal within normalCone() radians of normalAxis().
    const glm::vec3& centroid() const { return centroid_; }
    float boundRadius() const { return boundRadius_; }
    const glm::vec3& normalAxis() const { return normalAxis_; }
    float normalCone() const { return normalCone_; }

    // How the light is sampled from receiver point p: by solid angle if `bySolidAngle` and the
    // light qualifies there (few triangles, p in its near field, at least kMinSolidAngle; see
    // LightView), else by area.
    LightView view(const glm::vec3& p, bool bySolidAngle) const;
    // A point on the light as `v` (the view from receiver p) says to place it; u in [0,1)^2.
    LightPoint sample(LightView& v, const glm::vec3& p, glm::vec2 u) const {
        return v.solidAngle > 0.0f ? sampleBySolidAngle(v, p, u) : sample(u);
    }
    // 1 / pdf (solid angle) of a sample at distance^2 d2 whose light normal makes cos' with the
    // direction back to the receiver: what a light sample's radiance is weighted by.
    float inversePdf(const LightView& v, float cosLight, float d2) const {
        return v.solidAngle > 0.0f ? v.solidAngle : area_ * cosLight / d2;
    }
    // Unoccluded irradiance at x (unit normal n) per unit radiance, by Lambert's polygon formula
    // over the triangles facing x: exact where the light lies above x's horizon, an
    // underestimate where it crosses it. -1 for a light of more than LightView::kMaxTriangles
    // triangles.
    float irradianceEstimate(const glm::vec3& x, const glm::vec3& n) const;
    // Uniform by solid angle over the triangles facing p (v.solidAngle > 0).
    LightPoint sampleBySolidAngle(LightView& v, const glm::vec3& p, glm::vec2 u) const;

    // A point distributed uniformly by area over the light; u in [0,1)^2. Inline: it runs once
    // per light sample.
    LightPoint sample(glm::vec2 u) const {
        // Pick the triangle whose CDF interval holds u.x, then stretch that interval back to
        // [0,1). Few triangles (the usual quad light): a branchless count, since u.x is random
        // and a search would mispredict half its branches.
        std::size_t i = 0;
        const std::size_t n = tris_.size();
        if (n <= 16) {
            for (std::size_t k = 0; k + 1 < n; ++k) i += u.x >= tris_[k].cdf ? 1 : 0;
        } else {
            const auto it = std::upper_bound(cdfs_.begin(), cdfs_.end(), u.x);
            i = std::min(static_cast<std::size_t>(it - cdfs_.begin()), n - 1);
        }
        const Tri& t = tris_[i];
        const float ux = std::min(std::max((u.x - t.cdfLow) * t.invCdfWidth, 0.0f), 0x1.fffffep-1f);
        // Uniform point on the triangle (square-root warp).
        const float su = std::sqrt(ux);
        return {t.v0 + (su * (1.0f - u.y)) * t.e1 + (su * u.y) * t.e2, t.normal};
    }

    struct Tri {
        glm::vec3 v0, e1, e2, normal;
        float cdfLow;       // CDF before this triangle
        float cdf;          // CDF up to and including it
        float invCdfWidth;  // 1 / (cdf - cdfLow), 0 for an empty interval
    };
    // For path mode's SIMD light samples (tracer/path_simd.h), which place points as sample(u).
    const std::vector<Tri>& triangles() const { return tris_; }

private:
    glm::vec3 radiance_{0.0f};
    float area_ = 0.0f;
    float vertexScale_ = 0.0f;
    glm::vec3 centroid_{0.0f}, normalAxis_{0.0f, 0.0f, 1.0f};
    float boundRadius_ = 0.0f;
    float normalCone_ = 3.14159265f;  // pi: no useful cone
    std::vector<Tri> tris_;
    std::vector<float> cdfs_;  // Tri::cdf of each triangle, for the binary search; the last is exactly 1
};

// Point and spot lights with the angular profile resolved once.
struct PointLightSource {
    glm::vec3 position;
    glm::vec3 intensity;
    glm::vec3 normal;  // lobe: its axis; spot: the cone axis; else zero
    bool lobe;
    bool spot = false;
    float cosInner = 1.0f, cosOuter = 0.0f;  // spot cone (scene/lights.h spotFalloff)

    // The intensity's factor towards unit direction `out` (from the light to the receiver); 0
    // where it emits nothing. Every estimator and contribution() test the same value.
    float angular(const glm::vec3& out) const {
        const float c = normal.x * out.x + normal.y * out.y + normal.z * out.z;
        if (lobe) return c > 0.0f ? c : 0.0f;
        return spot ? spotFalloff(c, cosInner, cosOuter) : 1.0f;
    }
};

// A light infinitely far away in one direction (a sun): a delta light, one shadow ray to infinity.
struct DirectionalSource {
    glm::vec3 toLight;     // unit, from the receiver towards the light
    glm::vec3 irradiance;  // on a surface facing it
};

// All lights, plus what light selection and MIS need. Light index l < points.size() is a point
// light, the rest are areas[l - points.size()]. The lights at infinity (directional lights, the
// environment) are outside that numbering: every shading mode takes all of them at every hit, so
// they never enter light selection.
struct LightSet {
    std::vector<PointLightSource> points;
    std::vector<AreaLightSampler> areas;  // empty (zero-area) lights are dropped
    std::vector<DirectionalSource> directionals;  // black ones are dropped
    std::optional<EnvironmentSampler> environment;

    // Up to this many lights, direct lighting takes every light at every hit (the exact stratified
    // per-light estimator); beyond it, samples pick lights from the power CDF (docs/tracer.md).
    static constexpr std::size_t kFewLights = 8;
    std::size_t count() const { return points.size() + areas.size(); }
    bool many() const { return count() > kFewLights; }
    // Per-hit (contribution) selection builds its CDF in a stack array of this many entries, so
    // the hot path never allocates; scenes with more lights fall back to the global power CDF.
    static constexpr std::size_t kMaxPerHitLights = 64;
    bool perHitSelectable() const { return count() <= kMaxPerHitLights; }

    // Importance of light l at receiver x with unit shading normal n: its unoccluded irradiance
    // (luminance), estimated from the light's bounding sphere and normal cone. Conservative where
    // it matters for bias: 0 only if no point of the light can reach x from above n (then the
    // estimator's contribution is 0 too); at most pi L, a Lambertian emitter's irradiance cap.
    float contribution(std::size_t l, const glm::vec3& x, const glm::vec3& n) const;
    std::vector<float> luminance;  // per light: of the intensity (points) or radiance (areas)

    // Power-proportional selection over all lights: cdf.back() == 1, pdf[l] = P(l).
    std::vector<float> selectCdf, selectPdf;
    // Area light index (into `areas`) per scene triangle, -1 if the triangle is not a light. Only
    // filled when the scene has area lights (MIS needs the pdf of hitting a light).
    std::vector<std::int32_t> areaOfTriangle;

    // The light holding u in [0,1) on the CDF; u is rescaled to [0,1) within the light's interval
    // so one stratified number serves both the choice and the point on the light.
    std::size_t select(float& u) const {
        const std::size_t n = selectCdf.size();
        if (n == 1) return 0;  // u stays as it is: its interval is [0, 1)
        std::size_t i = static_cast<std::size_t>(std::upper_bound(selectCdf.begin(), selectCdf.end(), u) - selectCdf.begin());
        i = std::min(i, n - 1);
        const float low = i == 0 ? 0.0f : selectCdf[i - 1];
        const float width = selectCdf[i] - low;
        u = width > 0.0f ? std::min(std::max((u - low) / width, 0.0f), 0x1.fffffep-1f) : 0.0f;
        return i;
    }
};

// The entry holding u in [0,1) on cdf[0..n) (cdf[n-1] == 1), u rescaled within it as select().
inline std::size_t selectOnCdf(const float* cdf, std::size_t n, float& u) {
    std::size_t i = static_cast<std::size_t>(std::upper_bound(cdf, cdf + n, u) - cdf);
    i = std::min(i, n - 1);
    const float low = i == 0 ? 0.0f : cdf[i - 1];
    const float width = cdf[i] - low;
    u = width > 0.0f ? std::min(std::max((u - low) / width, 0.0f), 0x1.fffffep-1f) : 0.0f;
    return i;
}

LightSet buildLights(const Scene& scene, const EmbreeScene& geometry);

}  // namespace aamap
