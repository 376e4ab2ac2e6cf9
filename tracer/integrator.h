#pragma once
// Radiance along a ray: the shading budget of DESIGN.md section 2, separate from the primary-ray
// (antialiasing) budget. Direct light only for now: point lights with one shadow ray each and area
// lights with a stratified m x m pattern of shadow rays per hit, traced as 8-wide packets.
#include <algorithm>
#include <cmath>

#include <embree3/rtcore.h>
#include <glm/vec3.hpp>

#include "tracer/embree_scene.h"
#include "tracer/lights.h"
#include "tracer/ray_offset.h"
#include "tracer/sampler.h"
#include "tracer/tracer.h"

namespace aamap {

class Integrator {
public:
    Integrator(const EmbreeScene& geometry, const LightSet& lights, const ShadingSettings& shading);

    // Radiance arriving at `origin` from unit direction -dir. Counts every ray it traces in `rays`
    // (the primary ray in rays.primary). Allocates nothing.
    glm::vec3 primary(const glm::vec3& origin, const glm::vec3& dir, const Sampler& sampler, RayCounts& rays) const;

    int areaLightGrid() const { return lightGrid_; }  // m: m x m samples per area light per hit

private:
    struct SurfacePoint {
        glm::vec3 position;   // the hit point, where shading geometry is measured
        glm::vec3 origin;     // hit point pushed off the surface towards the viewer: rays start here
        glm::vec3 geometric;  // unit geometric normal on the viewer's side
        glm::vec3 shading;    // unit shading normal on the viewer's side
        const ShadingMaterial* material;
    };

    glm::vec3 shadeSurface(const SurfacePoint& sp, const Sampler& sampler, int depth, RayCounts& rays) const;
    // Reflected direct light (point + area lights) for a Lambertian surface.
    glm::vec3 directDiffuse(const SurfacePoint& sp, const Sampler& sampler, int depth, RayCounts& rays) const;
    // True if nothing blocks the segment from origin to target (a point light: nothing to stop
    // short of). Traces one shadow ray.
    bool unoccluded(const glm::vec3& origin, const glm::vec3& target, RayCounts& rays) const;

    const EmbreeScene& geometry_;
    const LightSet& lights_;
    RTCScene scene_;
    int lightGrid_;
};

}  // namespace aamap
