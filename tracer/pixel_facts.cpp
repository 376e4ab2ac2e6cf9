#include "tracer/pixel_facts.h"

#include <algorithm>
#include <array>
#include <cmath>

#include <glm/geometric.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "tracer/integrator.h"

namespace aamap {
namespace {

using namespace pixel_fact;

constexpr int kSubRays = kGrid * kGrid;
constexpr int kLightGrid = 2;  // area-light points per axis tested from each sub-hit
constexpr float kCreaseCos = 0.8660254f;  // cos 30 degrees

bool unoccluded(RTCScene scene, const glm::vec3& origin, const glm::vec3& target, float tfar) {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRay ray{};
    ray.org_x = origin.x;
    ray.org_y = origin.y;
    ray.org_z = origin.z;
    ray.dir_x = target.x - origin.x;  // unnormalised: t = 1 is the target
    ray.dir_y = target.y - origin.y;
    ray.dir_z = target.z - origin.z;
    ray.tnear = 0.0f;
    ray.tfar = tfar;
    ray.mask = ~0u;
    rtcOccluded1(scene, &context, &ray);
    return ray.tfar >= 0.0f;  // Embree sets tfar to -inf on a hit
}

// What one sub-ray found: its object (or none), its normal, and per light how much of it it sees
// (point lights 0 or 1; area lights the visible fraction of kLightGrid^2 points; -1 where the
// light is behind the surface, which says nothing about shadows).
struct SubHit {
    bool hit = false;
    std::uint32_t object = 0;
    glm::vec3 normal{0.0f};
    bool mirror = false;
};

}  // namespace

PixelFacts tracePixelFacts(const EmbreeScene& geometry, const LightSet& lights, const std::vector<std::uint32_t>& objects,
                           const PinholeCamera& camera, int width, int height, int threads) {
    PixelFacts facts(width, height);
    const ShadingSettings shading;
    const std::unique_ptr<Integrator> integrator = makeIntegrator(geometry, lights, shading);  // for intersect
    const std::size_t lightCount = lights.points.size() + lights.areas.size();
    const float invW = 1.0f / static_cast<float>(width), invH = 1.0f / static_cast<float>(height);

    const auto row = [&](int y) {
        std::vector<float> visibility(kSubRays * lightCount);
        for (int x = 0; x < width; ++x) {
            std::uint16_t bits = 0;
            std::array<SubHit, kSubRays> subs{};
            std::fill(visibility.begin(), visibility.end(), -1.0f);
            for (int s = 0; s < kSubRays; ++s) {
                // Stratum centres: the facts are a property of the pixel, not of a sample pattern.
                const float u = (static_cast<float>(x) + (static_cast<float>(s % kGrid) + 0.5f) / kGrid) * invW;
                const float v = (static_cast<float>(y) + (static_cast<float>(s / kGrid) + 0.5f) / kGrid) * invH;
                const glm::vec3 dir = glm::normalize(camera.direction(u, v));
                SurfaceHit hit;
                std::uint64_t counter = 0;
                if (!integrator->intersect(camera.origin, dir, hit, counter)) {
                    bits |= Background;
                    continue;
                }
                const ShadingMaterial& m = *hit.material;
                SubHit& sub = subs[s];
                sub.hit = true;
                sub.object = hit.primitive < objects.size() ? objects[hit.primitive] : 0;
                sub.normal = hit.shading;
                if (m.emissive) bits |= Emitter;
                if (m.kind == MaterialKind::Glass) bits |= Glass;
                if (m.kind == MaterialKind::Mirror) {
                    sub.mirror = true;
                    bits |= geometry.triangle(hit.primitive).flat ? PlanarMirror : CurvedMirror;
                }
                if (m.texture >= 0) bits |= pixel_fact::Texture;
                if (m.glossy) bits |= Glossy;
                if (m.kind != MaterialKind::Diffuse || m.emissive) continue;  // no direct-light shadow to speak of
                float* vis = visibility.data() + static_cast<std::size_t>(s) * lightCount;  // data(): no lights, no elements
                for (std::size_t l = 0; l < lights.points.size(); ++l) {
                    const PointLightSource& p = lights.points[l];
                    const glm::vec3 toLight = p.position - hit.position;
                    if (glm::dot(toLight, hit.geometric) <= 0.0f || p.angular(glm::normalize(-toLight)) <= 0.0f) continue;
                    vis[l] = unoccluded(geometry.handle(), hit.originFor(toLight), p.position, 1.0f - 1e-4f) ? 1.0f : 0.0f;
                }
                for (std::size_t a = 0; a < lights.areas.size(); ++a) {
                    const AreaLightSampler& light = lights.areas[a];
                    int seen = 0, facing = 0;
                    for (int j = 0; j < kLightGrid * kLightGrid; ++j) {
                        const glm::vec2 lu((static_cast<float>(j % kLightGrid) + 0.5f) / kLightGrid,
                                           (static_cast<float>(j / kLightGrid) + 0.5f) / kLightGrid);
                        const LightPoint q = light.sample(lu);
                        const glm::vec3 toLight = q.position - hit.position;
                        if (glm::dot(toLight, hit.geometric) <= 0.0f || glm::dot(q.normal, toLight) >= 0.0f) continue;
                        ++facing;
                        seen += unoccluded(geometry.handle(), hit.originFor(toLight), q.position, 1.0f - 1e-3f) ? 1 : 0;
                    }
                    if (facing > 0) vis[lights.points.size() + a] = static_cast<float>(seen) / static_cast<float>(facing);
                }
            }

            // Geometry: objects and normals across the sub-hits.
            const SubHit* first = nullptr;
            for (const SubHit& sub : subs) {
                if (!sub.hit) continue;
                if ((bits & Background) != 0) bits |= Silhouette;  // some hit, some escaped
                if (first == nullptr) {
                    first = &sub;
                    continue;
                }
                if (sub.object != first->object) bits |= Silhouette;
                else if (glm::dot(sub.normal, first->normal) < kCreaseCos) bits |= Crease;
                if (sub.mirror && first->mirror && glm::dot(sub.normal, first->normal) < 0.9999f) {
                    bits &= static_cast<std::uint16_t>(~PlanarMirror);
                    bits |= CurvedMirror;
                }
            }
            // Light: a light seen by some sub-hits and not others, or partly.
            for (std::size_t l = 0; l < lightCount; ++l) {
                float lo = 2.0f, hi = -1.0f;
                for (int s = 0; s < kSubRays; ++s) {
                    const float v = visibility[static_cast<std::size_t>(s) * lightCount + l];
                    if (v < 0.0f) continue;
                    lo = std::min(lo, v);
                    hi = std::max(hi, v);
                }
                if (hi < 0.0f) continue;
                const bool point = l < lights.points.size();
                if (point && lo < hi) bits |= ShadowBoundary;
                if (!point && (lo < hi || (lo > 0.0f && lo < 1.0f))) bits |= Penumbra;
            }
            facts.at(x, y) = bits;
        }
    };
    const auto all = [&] {
        tbb::parallel_for(tbb::blocked_range<int>(0, height), [&](const tbb::blocked_range<int>& r) {
            for (int y = r.begin(); y < r.end(); ++y) row(y);
        });
    };
    if (threads > 0) tbb::task_arena(threads).execute(all);
    else all();
    return facts;
}

}  // namespace aamap
