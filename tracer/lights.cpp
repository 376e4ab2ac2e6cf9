#include "tracer/lights.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>
#include <glm/geometric.hpp>
#include <spdlog/spdlog.h>

#include "tracer/embree_scene.h"
#include "tracer/spherical_triangle.h"

namespace aamap {

AreaLightSampler::AreaLightSampler(const AreaLight& light, const EmbreeScene& geometry) : radiance_(light.radiance) {
    double total = 0.0;
    std::vector<double> areas;
    for (std::uint32_t id : light.triangles) {
        if (id >= geometry.triangleCount())
            throw std::invalid_argument(fmt::format("area light '{}' names triangle {} of {}", light.name, id,
                                                    geometry.triangleCount()));
        const Triangle& t = geometry.triangle(id);
        const double a = 0.5 * glm::length(glm::dvec3(glm::cross(glm::dvec3(t.e1), glm::dvec3(t.e2))));
        if (!(a > 0.0)) continue;  // degenerate triangles cannot be sampled or hit
        tris_.push_back({t.v0, t.e1, t.e2, t.normal, 0.0f, 0.0f, 0.0f});
        vertexScale_ = std::max(vertexScale_, t.vertexScale);
        areas.push_back(a);
        total += a;
    }
    if (tris_.empty()) return;
    double running = 0.0;
    float low = 0.0f;
    for (std::size_t i = 0; i < tris_.size(); ++i) {
        running += areas[i];
        const float high = i + 1 == tris_.size() ? 1.0f : static_cast<float>(running / total);
        tris_[i].cdfLow = low;
        tris_[i].cdf = high;
        tris_[i].invCdfWidth = high > low ? 1.0f / (high - low) : 0.0f;
        cdfs_.push_back(high);
        low = high;
    }
    area_ = static_cast<float>(total);
    // Selection bounds: area-weighted centroid and normal, the farthest vertex, the widest normal.
    glm::dvec3 c(0.0), axis(0.0);
    for (std::size_t i = 0; i < tris_.size(); ++i) {
        const Tri& t = tris_[i];
        c += areas[i] * (glm::dvec3(t.v0) + (glm::dvec3(t.e1) + glm::dvec3(t.e2)) / 3.0);
        axis += areas[i] * glm::dvec3(t.normal);
    }
    centroid_ = glm::vec3(c / total);
    double r = 0.0;
    for (const Tri& t : tris_)
        for (const glm::vec3& v : {t.v0, t.v0 + t.e1, t.v0 + t.e2})
            r = std::max(r, glm::length(glm::dvec3(v) - glm::dvec3(centroid_)));
    boundRadius_ = static_cast<float>(r * 1.001 + 1e-6 * vertexScale_);  // float slack: stay a bound
    const double axisLength = glm::length(axis);
    if (axisLength > 1e-6 * total) {
        normalAxis_ = glm::vec3(axis / axisLength);
        double cone = 0.0;
        for (const Tri& t : tris_)
            cone = std::max(cone, std::acos(std::clamp(glm::dot(glm::dvec3(t.normal), axis / axisLength), -1.0, 1.0)));
        normalCone_ = static_cast<float>(std::min(cone + 1e-3, 3.14159265358979));
    }
    if (light.area > 0.0f && std::abs(light.area - area_) > 1e-3f * area_)
        spdlog::warn("area light '{}': declared area {} but its triangles cover {}; using the latter", light.name,
                     light.area, area_);
}

namespace {
// Distance from p to the triangle v0, v0 + e1, v0 + e2 with unit normal n: to its plane where
// p projects inside it, else to the nearest edge.
float distanceToTriangle(const glm::vec3& p, const glm::vec3& v0, const glm::vec3& e1, const glm::vec3& e2,
                         const glm::vec3& n) {
    const glm::vec3 w = p - v0;
    const float height = glm::dot(w, n);
    // Barycentrics of the projection (u along e1, v along e2).
    const float d11 = glm::dot(e1, e1), d12 = glm::dot(e1, e2), d22 = glm::dot(e2, e2);
    const float w1 = glm::dot(w, e1), w2 = glm::dot(w, e2);
    const float det = d11 * d22 - d12 * d12;
    if (det > 0.0f) {
        const float u = (d22 * w1 - d12 * w2) / det, v = (d11 * w2 - d12 * w1) / det;
        if (u >= 0.0f && v >= 0.0f && u + v <= 1.0f) return std::abs(height);
    }
    const auto toSegment = [&](const glm::vec3& a, const glm::vec3& e) {
        const float ee = glm::dot(e, e);
        const float t = ee > 0.0f ? std::clamp(glm::dot(p - a, e) / ee, 0.0f, 1.0f) : 0.0f;
        return glm::length(p - (a + t * e));
    };
    return std::min({toSegment(v0, e1), toSegment(v0, e2), toSegment(v0 + e1, e2 - e1)});
}
}  // namespace

LightView AreaLightSampler::view(const glm::vec3& p, bool bySolidAngle) const {
    LightView v;
    const std::size_t n = tris_.size();
    if (!bySolidAngle || n > static_cast<std::size_t>(LightView::kMaxTriangles)) return v;
    // Area sampling's solid-angle density, cos' / d^2 = h / d^3 (h: p's height over the plane),
    // spans (farthest / nearest point)^3 over a triangle. Where that stays within
    // kMaxDensityRatio, stratified area samples are close to uniform in solid angle already.
    float nearest = std::numeric_limits<float>::infinity(), farthest = 0.0f;
    for (const Tri& t : tris_) {
        if (!(glm::dot(t.normal, t.v0 - p) < 0.0f)) continue;  // faces away
        nearest = std::min(nearest, distanceToTriangle(p, t.v0, t.e1, t.e2, t.normal));
        for (const glm::vec3& corner : {t.v0, t.v0 + t.e1, t.v0 + t.e2})
            farthest = std::max(farthest, glm::length(corner - p));
    }
    const float ratio = farthest / nearest;
    if (!(ratio * ratio * ratio > LightView::kMaxDensityRatio)) return v;  // also: nothing faces p
    // Each triangle's solid angle, 0 for those that face away (a one-sided emitter sends
    // nothing to p from there, so they get no samples).
    float total = 0.0f;
    std::size_t lastUsed = 0;
    for (std::size_t i = 0; i < n; ++i) {
        const Tri& t = tris_[i];
        const glm::vec3 a = t.v0 - p;
        const float omega = glm::dot(t.normal, a) < 0.0f ? triangleSolidAngle(a, a + t.e1, a + t.e2) : 0.0f;
        if (omega > 0.0f) lastUsed = i;
        v.omega[i] = omega;
        total += omega;
        v.cdf[i] = total;
    }
    if (!(total >= LightView::kMinSolidAngle && total <= LightView::kMaxSolidAngle)) return v;
    // Pin the CDF's end at the last triangle facing p, so rounding cannot select one behind it.
    const float inv = 1.0f / total;
    for (std::size_t i = 0; i < n; ++i) v.cdf[i] = i >= lastUsed ? 1.0f : v.cdf[i] * inv;
    v.solidAngle = total;
    return v;
}

float AreaLightSampler::irradianceEstimate(const glm::vec3& x, const glm::vec3& n) const {
    if (tris_.size() > static_cast<std::size_t>(LightView::kMaxTriangles)) return -1.0f;
    // E / L = -1/2 sum over the edges (v_i, v_i+1) of their angle times n . unit(v_i x v_i+1),
    // vertices relative to x, in the winding that faces x.
    float sum = 0.0f;
    for (const Tri& t : tris_) {
        const glm::vec3 a = t.v0 - x;
        if (!(glm::dot(t.normal, a) < 0.0f)) continue;
        const glm::vec3 v[3] = {glm::normalize(a), glm::normalize(a + t.e1), glm::normalize(a + t.e2)};
        for (int i = 0; i < 3; ++i) {
            const glm::vec3& p = v[i];
            const glm::vec3& q = v[(i + 1) % 3];
            const glm::vec3 g = glm::cross(p, q);
            const float lg = glm::length(g);
            if (!(lg > 0.0f)) continue;
            sum += std::atan2(lg, glm::dot(p, q)) * glm::dot(n, g) / lg;
        }
    }
    const float e = -0.5f * sum;
    return std::isfinite(e) ? std::max(e, 0.0f) : 0.0f;
}

LightPoint AreaLightSampler::sampleBySolidAngle(LightView& v, const glm::vec3& p, glm::vec2 u) const {
    // The triangle whose CDF interval holds u.x (faced-away ones have empty intervals, never
    // selected), u.x stretched back to [0,1) within it.
    const std::size_t i = selectOnCdf(v.cdf, tris_.size(), u.x);
    const Tri& t = tris_[i];
    const glm::vec3 a = t.v0 - p;
    const LightPoint failed{p, glm::vec3(0.0f)};
    const std::uint32_t bit = 1u << i;
    if (!(v.ready & bit)) {
        v.ready |= bit;
        if (!v.spherical[i].setup(a, a + t.e1, a + t.e2, v.omega[i])) v.degenerate |= bit;
    }
    if (v.degenerate & bit) return failed;
    const glm::vec3 dir = v.spherical[i].sample(u);
    // Where the direction meets the triangle's plane.
    const float along = glm::dot(t.normal, dir);
    if (!(along < 0.0f)) return failed;
    const float distance = glm::dot(t.normal, a) / along;
    if (!(distance > 0.0f) || !std::isfinite(distance)) return failed;
    return {p + distance * dir, t.normal};
}

LightSet buildLights(const Scene& scene, const EmbreeScene& geometry) {
    LightSet set;
    std::vector<double> pointSolidAngles;  // power = intensity * this
    for (const PointLight& p : scene.pointLights) {
        const float len = glm::length(p.normal);
        const float spotLen = glm::length(p.spotDirection);
        PointLightSource s{p.position, p.intensity, glm::vec3(0.0f), len > 0.0f};
        if (s.lobe) {
            s.normal = p.normal / len;
        } else if (spotLen > 0.0f) {
            s.spot = true;
            s.normal = p.spotDirection / spotLen;
            s.cosInner = p.cosInner;
            s.cosOuter = std::min(p.cosOuter, p.cosInner);
        }
        set.points.push_back(s);
        pointSolidAngles.push_back(emittingSolidAngle(p));
    }
    std::vector<const AreaLight*> kept;  // the scene light behind each sampler
    for (const AreaLight& a : scene.areaLights) {
        AreaLightSampler s(a, geometry);
        if (s.empty()) {
            spdlog::warn("area light '{}' has no area; ignored", a.name);
            continue;
        }
        set.areas.push_back(std::move(s));
        kept.push_back(&a);
    }
    // Power: flux for area lights (pi L A), 4 pi I for isotropic points, pi I for cosine lobes,
    // I times the cone's solid-angle integral for spots (emittingSolidAngle). Luminance weights
    // the channels; a black light keeps a tiny share so no light is unreachable.
    const auto lum = [](const glm::vec3& c) { return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z; };
    std::vector<double> power;
    for (std::size_t i = 0; i < set.points.size(); ++i)
        power.push_back(pointSolidAngles[i] / 3.14159265358979 * lum(set.points[i].intensity));
    const auto addLuminance = [&](const glm::vec3& c) { set.luminance.push_back(static_cast<float>(std::max(lum(c), 0.0))); };
    for (const PointLightSource& p : set.points) addLuminance(p.intensity);
    for (const AreaLightSampler& a : set.areas) addLuminance(a.radiance());
    for (const AreaLightSampler& a : set.areas) power.push_back(static_cast<double>(a.area()) * lum(a.radiance()));
    double total = 0.0;
    for (double& w : power) total += (w = std::max(w * 3.14159265358979, 0.0));
    for (double& w : power) w = std::max(w, 1e-6 * total + 1e-30);
    total = 0.0;
    for (double w : power) total += w;
    double running = 0.0;
    for (std::size_t i = 0; i < power.size(); ++i) {
        running += power[i];
        set.selectPdf.push_back(static_cast<float>(power[i] / total));
        set.selectCdf.push_back(i + 1 == power.size() ? 1.0f : static_cast<float>(running / total));
    }
    for (const DirectionalLight& d : scene.directionalLights) {
        const float len = glm::length(d.direction);
        if (!(len > 0.0f) || !(std::max({d.irradiance.x, d.irradiance.y, d.irradiance.z}) > 0.0f)) continue;
        set.directionals.push_back({-d.direction / len, d.irradiance});
    }
    if (scene.environment) set.environment.emplace(*scene.environment);
    if (!set.areas.empty()) {
        set.areaOfTriangle.assign(geometry.triangleCount(), -1);
        for (std::size_t k = 0; k < kept.size(); ++k)
            for (std::uint32_t id : kept[k]->triangles) set.areaOfTriangle[id] = static_cast<std::int32_t>(k);
    }
    return set;
}

namespace {
constexpr float kPi = 3.14159265358979f;
// cos(max(0, alpha - slack)) for cos(alpha) = cosAlpha, clamped at 0: the largest cosine any
// direction within `slack` radians of the given one can reach.
float cosWithin(float cosAlpha, float slack) {
    const float alpha = std::acos(std::clamp(cosAlpha, -1.0f, 1.0f));
    return alpha <= slack ? 1.0f : std::max(0.0f, std::cos(alpha - slack));
}
}  // namespace

float LightSet::contribution(std::size_t l, const glm::vec3& x, const glm::vec3& n) const {
    const float lum = luminance[l];
    if (!(lum > 0.0f)) return 0.0f;  // black: contributes nothing
    if (l < points.size()) {
        // Exact, with the estimator's own tests, so 0 here means 0 there.
        const PointLightSource& p = points[l];
        const glm::vec3 w = p.position - x;
        const float d2 = glm::dot(w, w);
        if (!(d2 > 0.0f)) return 0.0f;
        const glm::vec3 dir = w * (1.0f / std::sqrt(d2));
        const float cosSurface = glm::dot(n, dir);
        const float lobe = p.angular(-dir);
        if (cosSurface <= 0.0f || lobe <= 0.0f) return 0.0f;
        const float e = lum * lobe * cosSurface / d2;
        return std::isfinite(e) ? e : lum;
    }
    const AreaLightSampler& a = areas[l - points.size()];
    const float cap = kPi * lum;  // irradiance from a Lambertian emitter never exceeds pi L
    const glm::vec3 w = a.centroid() - x;
    const float d2 = glm::dot(w, w);
    const float d = std::sqrt(d2);
    if (!(d > 1e-20f)) return cap;  // at the centroid: no direction to bound with
    const glm::vec3 dir = w * (1.0f / d);
    // Directions to the light's points lie within asin(r / d) of the centroid's (all directions
    // once inside the bounding sphere); its normals lie within the normal cone of the axis.
    const float spread = a.boundRadius() >= d ? 0.5f * kPi : std::asin(a.boundRadius() / d);
    const float cosReceiver = cosWithin(glm::dot(n, dir), spread);
    const float cosLight = cosWithin(-glm::dot(a.normalAxis(), dir), spread + a.normalCone());
    // Far field: L A cos cos' / d^2 with the bounded cosines; near field: the cap.
    float e = std::min(cap, lum * a.area() * cosReceiver * cosLight / d2);
    if (!std::isfinite(e)) e = cap;
    // Within two bounding radii the bound is loose (often the cap): take Lambert's polygon
    // formula instead (exact for the part above x's horizon), floored at a tenth of the bound so
    // that no light that may reach x loses all its samples.
    if (e > 0.0f && d < 2.0f * a.boundRadius()) {
        const float estimate = a.irradianceEstimate(x, n);
        if (estimate >= 0.0f) e = std::max(std::min(lum * estimate, e), 0.1f * e);
    }
    return e;
}

}  // namespace aamap
