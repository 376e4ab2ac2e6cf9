#version 460
// The geometric aamap's raster: world normal, view depth and ids per texel (no shading).
#extension GL_GOOGLE_include_directive : require
#include "snapshot_interface.h"

layout(location = GEOMETRY_LOCATION_POSITION) in vec3 inPosition;
layout(location = GEOMETRY_LOCATION_NORMAL) in vec3 inNormal;
layout(location = GEOMETRY_LOCATION_IDS) in uvec2 inIds;  // object, material

layout(location = 0) out vec3 worldPosition;
layout(location = 1) out vec3 worldNormal;
layout(location = 2) flat out uvec2 ids;

layout(push_constant) uniform Push { GeometryPush pc; };

void main() {
    worldPosition = inPosition;
    worldNormal = inNormal;
    ids = inIds;
    gl_Position = pc.viewProj * vec4(inPosition, 1.0);
}
