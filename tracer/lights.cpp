#include "tracer/lights.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>
#include <glm/geometric.hpp>
#include <spdlog/spdlog.h>

#include "tracer/embree_scene.h"

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
    const float e = std::min(cap, lum * a.area() * cosReceiver * cosLight / d2);
    return std::isfinite(e) ? e : cap;
}

}  // namespace aamap
