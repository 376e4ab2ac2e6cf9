#version 460
// The Snapshot raster: world-space position and normal for per-pixel Lambert shading.
#extension GL_GOOGLE_include_directive : require
#include "snapshot_interface.h"

layout(location = GBUFFER_LOCATION_POSITION) in vec3 inPosition;
layout(location = GBUFFER_LOCATION_NORMAL) in vec3 inNormal;
layout(location = GBUFFER_LOCATION_KD) in vec3 inKd;
layout(location = GBUFFER_LOCATION_KE) in vec3 inKe;

layout(location = 0) out vec3 worldPosition;
layout(location = 1) out vec3 worldNormal;
layout(location = 2) flat out vec3 kd;
layout(location = 3) flat out vec3 ke;

layout(push_constant) uniform Push { GBufferPush pc; };

void main() {
    worldPosition = inPosition;
    worldNormal = inNormal;
    kd = inKd;
    ke = inKe;
    gl_Position = pc.viewProj * vec4(inPosition, 1.0);
}
