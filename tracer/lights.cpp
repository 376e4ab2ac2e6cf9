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
    if (light.area > 0.0f && std::abs(light.area - area_) > 1e-3f * area_)
        spdlog::warn("area light '{}': declared area {} but its triangles cover {}; using the latter", light.name,
                     light.area, area_);
}

LightSet buildLights(const Scene& scene, const EmbreeScene& geometry) {
    LightSet set;
    for (const PointLight& p : scene.pointLights) {
        const float len = glm::length(p.normal);
        const bool lobe = len > 0.0f;
        set.points.push_back({p.position, p.intensity, lobe ? p.normal / len : glm::vec3(0.0f), lobe});
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
    // Power: flux for area lights (pi L A), 4 pi I for isotropic points, pi I for cosine lobes.
    // Luminance weights the channels; a black light keeps a tiny share so no light is unreachable.
    const auto lum = [](const glm::vec3& c) { return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z; };
    std::vector<double> power;
    for (const PointLightSource& p : set.points) power.push_back((p.lobe ? 1.0 : 4.0) * lum(p.intensity));
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
    if (!set.areas.empty()) {
        set.areaOfTriangle.assign(geometry.triangleCount(), -1);
        for (std::size_t k = 0; k < kept.size(); ++k)
            for (std::uint32_t id : kept[k]->triangles) set.areaOfTriangle[id] = static_cast<std::int32_t>(k);
    }
    return set;
}

}  // namespace aamap
