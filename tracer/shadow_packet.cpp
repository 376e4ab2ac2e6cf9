#include "tracer/shadow_packet.h"

#include <algorithm>
#include <cmath>

#include "tracer/ray_offset.h"

namespace aamap {

void ShadowBatch8::prepare(int count, const glm::vec3& p, const glm::vec3& o, const glm::vec3& g,
                           const glm::vec3& s, float lightVertexScale, bool bySolidAngle) {
    const float vertexFloor = kVertexScaleShare * lightVertexScale;
    alignas(32) float tfar[kWidth];
    alignas(32) float dx[kWidth], dy[kWidth], dz[kWidth];
    alignas(32) int ok[kWidth];
    for (int i = 0; i < kWidth; ++i) {
        // Shading geometry from the true hit point.
        const float wx = qx[i] - p.x, wy = qy[i] - p.y, wz = qz[i] - p.z;
        const float d2 = wx * wx + wy * wy + wz * wz;
        const float inv = 1.0f / std::sqrt(d2);
        const float lx = wx * inv, ly = wy * inv, lz = wz * inv;
        const float cosGeom = g.x * lx + g.y * ly + g.z * lz;  // side test: no ray into the surface
        const float cosSurface = s.x * lx + s.y * ly + s.z * lz;
        const float cosLight = -(nx[i] * lx + ny[i] * ly + nz[i] * lz);
        weight[i] = bySolidAngle ? cosSurface : cosSurface * cosLight / d2;
        // The segment from the offset origin to the sample, ending the light's own offset short
        // of it. The direction stays unnormalised (t = 1 at the sample), and 1/|q - p| stands in
        // for 1/|q - o|: they differ by the offset, which only scales a tolerance.
        dx[i] = qx[i] - o.x;
        dy[i] = qy[i] - o.y;
        dz[i] = qz[i] - o.z;
        // rayOffset(q, light's vertex scale) / distance
        tfar[i] = 1.0f - kRayOffsetRelative * std::max(offsetScale(qx[i], qy[i], qz[i]), vertexFloor) * inv;
        ok[i] = (d2 > 0.0f) & (cosGeom > 0.0f) & (cosSurface > 0.0f) & (cosLight > 0.0f) & (tfar[i] > 0.0f);
    }
    for (int i = 0; i < kWidth; ++i) {
        valid[i] = (i < count && ok[i]) ? -1 : 0;
        setShadowLane(packet, i, o, {dx[i], dy[i], dz[i]}, valid[i] ? tfar[i] : 0.0f);
    }
}

float ShadowBatch8::trace(RTCScene scene, int count, RayCounts& rays) {
    int active = 0;
    for (int i = 0; i < count; ++i) active += valid[i] != 0;
    if (active == 0) return 0.0f;
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    rtcOccluded8(valid, scene, &context, &packet);
    rays.shadow += static_cast<std::uint64_t>(active);
    float sum = 0.0f;
    for (int i = 0; i < count; ++i)
        if (valid[i] && packet.tfar[i] >= 0.0f) sum += weight[i];  // Embree sets tfar to -inf on a hit
    return sum;
}

}  // namespace aamap
