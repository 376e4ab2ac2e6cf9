// Candidate points for the irradiance cache pre-pass: first hits of a coarse grid of camera rays.
#include <algorithm>
#include <limits>
#include <stdexcept>

#include <embree3/rtcore.h>
#include <fmt/format.h>
#include <glm/geometric.hpp>

#include "scene/camera.h"
#include "tracer/embree_scene.h"
#include "tracer/irradiance_cache.h"

namespace aamap {
namespace {

// Grid points (x, y) in coarse-to-fine order: all multiples of the largest power-of-two step
// first, then at each halved step the points not visited yet, each pass in raster order.
std::vector<std::pair<int, int>> coarseToFine(int w, int h) {
    int step = 1;
    while (step * 2 < std::max(w, h)) step *= 2;
    std::vector<std::pair<int, int>> order;
    order.reserve(static_cast<std::size_t>(w) * h);
    for (int s = step; s >= 1; s /= 2)
        for (int y = 0; y < h; y += s)
            for (int x = 0; x < w; x += s)
                if (s == step || x % (2 * s) != 0 || y % (2 * s) != 0) order.emplace_back(x, y);
    return order;
}

}  // namespace

std::vector<CachePoint> cameraCachePoints(const EmbreeScene& geometry, const PinholeCamera& camera, int gridW,
                                          int gridH) {
    if (gridW <= 0 || gridH <= 0)
        throw std::invalid_argument(fmt::format("cache point grid {}x{} is empty", gridW, gridH));
    std::vector<CachePoint> points;
    RTCIntersectContext context;
    for (const auto& [x, y] : coarseToFine(gridW, gridH)) {
        const float u = (static_cast<float>(x) + 0.5f) / static_cast<float>(gridW);
        const float v = (static_cast<float>(y) + 0.5f) / static_cast<float>(gridH);
        const glm::vec3 dir = glm::normalize(camera.direction(u, v));
        rtcInitIntersectContext(&context);
        RTCRayHit rh = makeRayHit(camera.origin, dir);
        rtcIntersect1(geometry.handle(), &context, &rh);
        if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) continue;
        const Triangle& tri = geometry.triangle(rh.hit.primID);
        const bool front = glm::dot(tri.normal, dir) < 0.0f;
        // An emitter that reflects nothing diffusely shows only Ke and direct light: no records.
        const ShadingMaterial& m = geometry.material(tri.material);
        if (m.emissive && front && !m.diffuse) continue;
        // As the integrator does: the point from the triangle, normals on the viewer's side.
        const glm::vec3 p = tri.v0 + rh.hit.u * tri.e1 + rh.hit.v * tri.e2;
        const glm::vec3 ng = front ? tri.normal : -tri.normal;
        glm::vec3 ns = geometry.shadingNormal(rh.hit.primID, rh.hit.u, rh.hit.v);
        if (glm::dot(ns, ng) < 0.0f) ns = -ns;
        points.push_back({p, ns});
    }
    return points;
}

}  // namespace aamap
