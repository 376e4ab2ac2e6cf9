#pragma once
// Up to W rays traced by one rtcIntersect4/8 call: a pixel's coherent primary rays, or the next
// segments of path mode's paths. On the stack: nothing is allocated per ray. Lane i holds exactly
// the ray rtcIntersect1 would get (makeRayHit), so a lane's hit equals the single-ray one.
#include <embree3/rtcore.h>
#include <glm/vec3.hpp>

#include "tracer/embree_scene.h"

namespace aamap {

template <int W>
struct RayPacketTypes;
template <>
struct RayPacketTypes<4> {
    using RayHit = RTCRayHit4;
    static void intersect(const int* valid, RTCScene s, RTCIntersectContext* c, RayHit* r) { rtcIntersect4(valid, s, c, r); }
};
template <>
struct RayPacketTypes<8> {
    using RayHit = RTCRayHit8;
    static void intersect(const int* valid, RTCScene s, RTCIntersectContext* c, RayHit* r) { rtcIntersect8(valid, s, c, r); }
};

template <int W>
struct RayPacket {
    static constexpr int kWidth = W;
    typename RayPacketTypes<W>::RayHit rays;  // carries its own alignment
    glm::vec3 dir[kWidth];

    void set(int lane, const glm::vec3& origin, const glm::vec3& d) {
        const RTCRayHit single = makeRayHit(origin, d);
        rays.ray.org_x[lane] = single.ray.org_x;
        rays.ray.org_y[lane] = single.ray.org_y;
        rays.ray.org_z[lane] = single.ray.org_z;
        rays.ray.dir_x[lane] = single.ray.dir_x;
        rays.ray.dir_y[lane] = single.ray.dir_y;
        rays.ray.dir_z[lane] = single.ray.dir_z;
        rays.ray.tnear[lane] = single.ray.tnear;
        rays.ray.tfar[lane] = single.ray.tfar;
        rays.ray.time[lane] = single.ray.time;
        rays.ray.mask[lane] = single.ray.mask;
        rays.ray.id[lane] = static_cast<unsigned>(lane);
        rays.ray.flags[lane] = 0;
        rays.hit.geomID[lane] = RTC_INVALID_GEOMETRY_ID;
        rays.hit.instID[0][lane] = RTC_INVALID_GEOMETRY_ID;
        dir[lane] = d;
    }
    // A lane that is masked off still holds finite data (Embree may read it).
    void setIdle(int lane) { set(lane, glm::vec3(0.0f), glm::vec3(0.0f, 0.0f, 1.0f)); }

    // Traces the lanes whose valid[] entry is -1. coherent: the rays share an origin and nearly a
    // direction (primary rays of one pixel), which Embree's packet traversal exploits.
    void trace(RTCScene scene, const int* valid, bool coherent) {
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        context.flags = coherent ? RTC_INTERSECT_CONTEXT_FLAG_COHERENT : RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
        RayPacketTypes<W>::intersect(valid, scene, &context, &rays);
    }
    // Traces lanes [0, count).
    void traceFirst(RTCScene scene, int count, bool coherent) {
        alignas(32) int valid[kWidth];
        for (int lane = 0; lane < kWidth; ++lane) valid[lane] = lane < count ? -1 : 0;
        trace(scene, valid, coherent);
    }

    bool missed(int lane) const { return rays.hit.geomID[lane] == RTC_INVALID_GEOMETRY_ID; }

    // Lane `lane` as the single-ray result the integrator takes.
    RTCRayHit hit(int lane) const {
        RTCRayHit rh{};
        rh.ray.org_x = rays.ray.org_x[lane];
        rh.ray.org_y = rays.ray.org_y[lane];
        rh.ray.org_z = rays.ray.org_z[lane];
        rh.ray.dir_x = rays.ray.dir_x[lane];
        rh.ray.dir_y = rays.ray.dir_y[lane];
        rh.ray.dir_z = rays.ray.dir_z[lane];
        rh.ray.tnear = rays.ray.tnear[lane];
        rh.ray.tfar = rays.ray.tfar[lane];
        rh.ray.mask = rays.ray.mask[lane];
        rh.hit.Ng_x = rays.hit.Ng_x[lane];
        rh.hit.Ng_y = rays.hit.Ng_y[lane];
        rh.hit.Ng_z = rays.hit.Ng_z[lane];
        rh.hit.u = rays.hit.u[lane];
        rh.hit.v = rays.hit.v[lane];
        rh.hit.primID = rays.hit.primID[lane];
        rh.hit.geomID = rays.hit.geomID[lane];
        rh.hit.instID[0] = rays.hit.instID[0][lane];
        return rh;
    }
};

}  // namespace aamap
