#pragma once
// Shadow rays that share an origin (the m x m samples of one area light seen from one hit) are
// traced as 8-wide Embree packets: one traversal serves the lot, and the rays are coherent since
// they aim at the same light. The batch keeps lane i = sample i, so results do not depend on
// which samples were culled, and the per-lane math is plain loops over float arrays that the
// compiler vectorises.
#include <cstdint>

#include <embree3/rtcore.h>
#include <glm/vec3.hpp>

#include "tracer/tracer_types.h"

namespace aamap {

// Lane i of an 8-wide shadow packet: the segment origin + t dir, t in [0, tfar].
inline void setShadowLane(RTCRay8& packet, int i, const glm::vec3& origin, const glm::vec3& dir, float tfar) {
    packet.org_x[i] = origin.x;
    packet.org_y[i] = origin.y;
    packet.org_z[i] = origin.z;
    packet.dir_x[i] = dir.x;
    packet.dir_y[i] = dir.y;
    packet.dir_z[i] = dir.z;
    packet.tnear[i] = 0.0f;
    packet.tfar[i] = tfar;
    packet.time[i] = 0.0f;
    packet.mask[i] = ~0u;
    packet.id[i] = static_cast<unsigned>(i);
    packet.flags[i] = 0;
}

struct ShadowBatch8 {
    static constexpr int kWidth = 8;

    alignas(32) float qx[kWidth], qy[kWidth], qz[kWidth];  // light sample positions
    alignas(32) float nx[kWidth], ny[kWidth], nz[kWidth];  // light normals at the samples
    alignas(32) float weight[kWidth];                      // cos cos' / d^2 (by solid angle: cos) where valid
    alignas(32) int valid[kWidth];                         // -1: trace this lane
    RTCRay8 packet;                                        // carries its own 32-byte alignment

    void setSample(int i, const glm::vec3& q, const glm::vec3& n) {
        qx[i] = q.x;
        qy[i] = q.y;
        qz[i] = q.z;
        nx[i] = n.x;
        ny[i] = n.y;
        nz[i] = n.z;
    }
    // Fills lanes [count, 8) with copies of lane count - 1, so every lane holds finite data.
    void padFrom(int count) {
        const int last = count - 1;
        for (int i = count; i < kWidth; ++i)
            setSample(i, {qx[last], qy[last], qz[last]}, {nx[last], ny[last], nz[last]});
    }

    // For lanes [0, count): computes the weights and the shadow segments from `origin` (the
    // offset hit point) to each sample, stopping short of the light by the scale-aware offset;
    // `position`, `geometric`, `shading` describe the hit. Lanes that face away are invalid.
    // `lightVertexScale` is the light's Triangle::vertexScale (ray_offset.h). bySolidAngle: the
    // samples were placed by solid angle, so a lane weighs cos alone (the caller multiplies by
    // the solid angle, not by the area).
    void prepare(int count, const glm::vec3& position, const glm::vec3& origin, const glm::vec3& geometric,
                 const glm::vec3& shading, float lightVertexScale, bool bySolidAngle);

    // Traces the valid lanes and returns the sum of the weights of the unoccluded ones, in lane
    // order. Adds the rays traced to rays.shadow.
    float trace(RTCScene scene, int count, RayCounts& rays);
    // After trace(): lane i was traced and reached the light.
    bool visible(int i) const { return valid[i] != 0 && packet.tfar[i] >= 0.0f; }
};

}  // namespace aamap
