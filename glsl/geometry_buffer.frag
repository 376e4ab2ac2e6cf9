#version 460
// Writes the two images of geometric_edges.h: normal (turned towards the camera, as the tracer
// and the Snapshot shading do) and view depth; object and material id.
#extension GL_GOOGLE_include_directive : require
#include "snapshot_interface.h"

layout(location = 0) in vec3 worldPosition;
layout(location = 1) in vec3 worldNormal;
layout(location = 2) flat in uvec2 ids;

layout(location = 0) out vec4 outNormalDepth;
layout(location = 1) out vec4 outIds;

layout(push_constant) uniform Push { GeometryPush pc; };

void main() {
    const vec3 toEye = pc.cameraPos.xyz - worldPosition;
    vec3 n = normalize(worldNormal);
    if (dot(n, toEye) < 0.0) n = -n;
    // > 0 for anything in front of the near plane; the clear value 0 marks uncovered texels.
    const float depth = max(dot(worldPosition - pc.cameraPos.xyz, pc.cameraForward.xyz), 1e-30);
    outNormalDepth = vec4(n, depth);
    outIds = vec4(float(ids.x & 0xffffffu), float(ids.y & 0xffffffu), 0.0, 0.0);
}
