#include "passes/view_budget.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

namespace aamap::passes {

ViewFrustum ViewFrustum::fromViewProjection(const glm::mat4& viewProj, float margin) {
    // Rows of the matrix (glm is column-major: m[col][row]).
    auto row = [&](int r) { return glm::vec4(viewProj[0][r], viewProj[1][r], viewProj[2][r], viewProj[3][r]); };
    const glm::vec4 x = row(0), y = row(1), w = row(3);
    const float s = 1.0f + margin;
    ViewFrustum f;
    f.planes = {s * w + x, s * w - x, s * w + y, s * w - y, w};
    for (glm::vec4& p : f.planes) {
        const float len = glm::length(glm::vec3(p));
        if (len > 0.0f) p /= len;
    }
    return f;
}

bool ViewFrustum::triangleOutside(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) const {
    for (const glm::vec4& p : planes) {
        const glm::vec3 n(p);
        if (glm::dot(n, a) + p.w < 0.0f && glm::dot(n, b) + p.w < 0.0f && glm::dot(n, c) + p.w < 0.0f) return true;
    }
    return false;
}

Bounds visibleRegion(const glm::mat4& viewProj, const Bounds& scene) {
    const glm::mat4 inverse = glm::inverse(viewProj);
    glm::vec3 lo(INFINITY), hi(-INFINITY);
    for (int i = 0; i < 8; ++i) {
        const glm::vec4 ndc((i & 1) ? 1.0f : -1.0f, (i & 2) ? 1.0f : -1.0f, (i & 4) ? 1.0f : 0.0f, 1.0f);
        const glm::vec4 p = inverse * ndc;
        if (!(std::abs(p.w) > 0.0f)) return scene;
        const glm::vec3 q = glm::vec3(p) / p.w;
        lo = glm::min(lo, q);
        hi = glm::max(hi, q);
    }
    Bounds region{glm::max(lo, scene.lo), glm::min(hi, scene.hi)};
    for (int a = 0; a < 3; ++a)
        if (!(region.lo[a] <= region.hi[a]) || !std::isfinite(region.lo[a]) || !std::isfinite(region.hi[a]))
            return scene;  // the frustum misses the bounds (or is degenerate): the whole scene
    return region;
}

double meanSolidAngle(double area, const glm::vec3& centre, const glm::vec3& normal, const Bounds& region) {
    if (!(area > 0.0)) return 0.0;
    const bool oneSided = glm::length(normal) > 0.0f;
    const glm::dvec3 n = oneSided ? glm::normalize(glm::dvec3(normal)) : glm::dvec3(0.0);
    double sum = 0.0;
    for (int i = 0; i < 27; ++i) {
        const glm::dvec3 t(0.5 * (i % 3), 0.5 * ((i / 3) % 3), 0.5 * (i / 9));
        const glm::dvec3 p = glm::dvec3(region.lo) + t * (glm::dvec3(region.hi) - glm::dvec3(region.lo));
        const glm::dvec3 d = p - glm::dvec3(centre);
        const double d2 = glm::dot(d, d);
        const double cosine = !oneSided ? 1.0 : d2 > 0.0 ? std::max(0.0, glm::dot(n, d) / std::sqrt(d2)) : 0.0;
        sum += area * cosine / std::max(d2, area);
    }
    return sum / 27.0;
}

int areaLightSamplesFor(double solidAngle, double solidAnglePerSample, int maxSamples) {
    maxSamples = std::max(maxSamples, 1);
    if (!(solidAnglePerSample > 0.0)) return maxSamples;
    const double n = std::ceil(solidAngle / solidAnglePerSample);
    if (!(n >= 1.0)) return 1;
    return n >= maxSamples ? maxSamples : static_cast<int>(n);
}

std::vector<std::uint32_t> trianglesInView(std::span<const glm::vec3> positions, std::uint32_t triangles,
                                           const ViewFrustum& frustum) {
    std::vector<std::uint32_t> kept;
    kept.reserve(triangles);
    for (std::uint32_t t = 0; t < triangles && 3 * static_cast<std::size_t>(t) + 2 < positions.size(); ++t)
        if (!frustum.triangleOutside(positions[3 * t], positions[3 * t + 1], positions[3 * t + 2])) kept.push_back(t);
    return kept;
}

void cullShadowCasters(std::span<const glm::vec3> positions, std::span<const std::uint32_t> faceIndices,
                       const glm::vec3& light, float patchRadius, const ViewFrustum& frustum,
                       std::vector<std::uint32_t>& out) {
    glm::vec4 planes[5];
    int count = 0;
    for (const glm::vec4& p : frustum.planes)
        if (glm::dot(glm::vec3(p), light) + p.w >= patchRadius) planes[count++] = p;
    for (std::size_t i = 0; i + 2 < faceIndices.size(); i += 3) {
        const glm::vec3& a = positions[faceIndices[i]];
        const glm::vec3& b = positions[faceIndices[i + 1]];
        const glm::vec3& c = positions[faceIndices[i + 2]];
        bool outside = false;
        for (int k = 0; k < count && !outside; ++k) {
            const glm::vec3 n(planes[k]);
            outside = glm::dot(n, a) + planes[k].w < 0.0f && glm::dot(n, b) + planes[k].w < 0.0f &&
                      glm::dot(n, c) + planes[k].w < 0.0f;
        }
        if (!outside) out.insert(out.end(), {faceIndices[i], faceIndices[i + 1], faceIndices[i + 2]});
    }
}

std::vector<glm::vec3> shadowReceivers(const ShadowNeedView& view) {
    std::vector<glm::vec3> receivers;
    const glm::mat4 inverse = glm::inverse(view.viewProj);
    constexpr int kGrid = 5;
    for (int j = 0; j < kGrid; ++j)
        for (int i = 0; i < kGrid; ++i) {
            // A point on the ray through the cell's centre, in front of the eye (any depth in (0, 1)).
            const glm::vec4 ndc(-1.0f + (2.0f * i + 1.0f) / kGrid, -1.0f + (2.0f * j + 1.0f) / kGrid, 0.5f, 1.0f);
            const glm::vec4 q = inverse * ndc;
            if (!(std::abs(q.w) > 0.0f)) continue;
            const glm::vec3 d = glm::vec3(q) / q.w - view.eye;
            if (!(glm::dot(d, d) > 0.0f)) continue;
            const glm::vec3 dir = glm::normalize(d);
            // The ray's segment inside the region (slabs).
            float t0 = 0.0f, t1 = INFINITY;
            for (int a = 0; a < 3; ++a) {
                if (std::abs(dir[a]) < 1e-12f) {
                    if (view.eye[a] < view.region.lo[a] || view.eye[a] > view.region.hi[a]) t1 = -1.0f;
                    continue;
                }
                float ta = (view.region.lo[a] - view.eye[a]) / dir[a];
                float tb = (view.region.hi[a] - view.eye[a]) / dir[a];
                if (ta > tb) std::swap(ta, tb);
                t0 = std::max(t0, ta);
                t1 = std::min(t1, tb);
            }
            if (!(t1 > t0) || !std::isfinite(t1)) continue;
            for (const float f : {0.25f, 0.5f, 0.75f, 1.0f}) receivers.push_back(view.eye + (t0 + f * (t1 - t0)) * dir);
        }
    return receivers;
}

std::vector<int> shadowFaceSizes(std::span<const PointLight> lights, double otherIrradiance, const ShadowNeedView& view,
                                 float texelPixels, int maxSize) {
    maxSize = std::max(maxSize, 1);
    const int minSize = std::min(kMinShadowFaceSize, maxSize);
    std::vector<int> sizes(lights.size(), maxSize);
    if (!(texelPixels > 0.0f) || lights.empty()) return sizes;
    const std::vector<glm::vec3> receivers = shadowReceivers(view);
    if (receivers.empty()) return sizes;  // nothing known of what is seen: the full resolution
    // Pixels per world unit across the view at clip depth w: half the raster times the length of
    // clip x's (or y's) row over w, the finer of the two.
    auto row = [&](int r) {
        return glm::vec3(view.viewProj[0][r], view.viewProj[1][r], view.viewProj[2][r]);
    };
    const double pixelsPerUnitAtDepthOne =
        0.5 * std::max(view.pixels.x * glm::length(row(0)), view.pixels.y * glm::length(row(1)));
    std::vector<double> need(lights.size(), 0.0), irradiance(lights.size());
    for (const glm::vec3& p : receivers) {
        const glm::vec4 clip = view.viewProj * glm::vec4(p, 1.0f);
        if (!(clip.w > 0.0f)) continue;
        const double pixelsPerUnit = pixelsPerUnitAtDepthOne / clip.w;
        double total = std::max(otherIrradiance, 0.0);
        for (std::size_t i = 0; i < lights.size(); ++i) {
            const PointLight& l = lights[i];
            const glm::vec3 r = p - l.position;
            const double d2 = glm::dot(r, r);
            const double lum = 0.2126 * l.intensity.x + 0.7152 * l.intensity.y + 0.0722 * l.intensity.z;
            const glm::vec3 out = d2 > 0.0 ? r / static_cast<float>(std::sqrt(d2)) : glm::vec3(0.0f);
            irradiance[i] = d2 > 0.0 ? std::max(lum, 0.0) * emissionFactor(l, out) / d2 : 0.0;
            total += irradiance[i];
        }
        if (!(total > 0.0) || !std::isfinite(total)) continue;
        for (std::size_t i = 0; i < lights.size(); ++i) {
            const double distance = glm::length(p - lights[i].position);
            // A texel spans at most 2 d / size here, which is (2 d / size) pixelsPerUnit pixels.
            const double share = irradiance[i] / total;
            need[i] = std::max(need[i], 2.0 * distance * pixelsPerUnit * share / texelPixels);
        }
    }
    for (std::size_t i = 0; i < lights.size(); ++i) {
        if (!std::isfinite(need[i])) continue;  // stays maxSize
        const double steps = std::ceil(need[i] / kShadowFaceStep);
        const int size = steps * kShadowFaceStep >= maxSize ? maxSize : static_cast<int>(steps) * kShadowFaceStep;
        sizes[i] = std::clamp(size, minSize, maxSize);
    }
    return sizes;
}

}  // namespace aamap::passes
