// The geometric aamap's vertex stage, included by geometry_buffer.vert and .textured.vert
// (GEOMETRY_TEXTURED: also uv and the material's atlas entry): the G-buffer's vertices, with the
// ids of their triangle from a storage buffer (the G-buffer's vertices carry none).
#extension GL_GOOGLE_include_directive : require
#include "snapshot_interface.h"

layout(location = GEOMETRY_LOCATION_POSITION) in vec3 inPosition;
layout(location = GEOMETRY_LOCATION_NORMAL) in vec3 inNormal;
layout(std430, binding = GEOMETRY_BINDING_IDS) readonly buffer TriangleIds { uvec2 triangleIds[]; };

layout(location = 0) out vec3 worldPosition;
layout(location = 1) out vec3 worldNormal;
layout(location = 2) flat out uvec2 ids;

#ifdef GEOMETRY_TEXTURED
layout(location = GEOMETRY_LOCATION_UV) in vec2 inUv;
layout(location = GEOMETRY_LOCATION_TEX_RECT) in uvec4 inTexRect;
layout(location = GEOMETRY_LOCATION_TEX_PARAMS) in vec2 inTexParams;
layout(location = 3) out vec2 uv;
layout(location = 4) flat out uvec4 texRect;
layout(location = 5) flat out vec2 texParams;
#endif

layout(push_constant) uniform Push { GeometryPush pc; };

void main() {
    worldPosition = inPosition;
    worldNormal = inNormal;
    ids = triangleIds[gl_VertexIndex / 3];  // unindexed draw: three vertices per triangle
#ifdef GEOMETRY_TEXTURED
    uv = inUv;
    texRect = inTexRect;
    texParams = inTexParams;
#endif
    gl_Position = pc.viewProj * vec4(inPosition, 1.0);
}
