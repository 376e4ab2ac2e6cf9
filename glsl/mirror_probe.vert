#version 460
// The curved mirror triangles from the camera (passes/mirror_probes.h), with their normals, the
// reflectance and the probe's first layer.
#extension GL_GOOGLE_include_directive : require
#include "snapshot_interface.h"

layout(location = MIRROR_PROBE_LOCATION_POSITION) in vec3 inPosition;
layout(location = MIRROR_PROBE_LOCATION_NORMAL) in vec3 inNormal;
layout(location = MIRROR_PROBE_LOCATION_REFLECTANCE) in vec3 inReflectance;
layout(location = MIRROR_PROBE_LOCATION_LAYER) in float inLayer;

layout(location = 0) out vec3 worldPosition;
layout(location = 1) out vec3 worldNormal;
layout(location = 2) flat out vec3 reflectance;
layout(location = 3) flat out float firstLayer;

layout(push_constant) uniform Push { MirrorProbePush pc; };

// As in gbuffer_vertex.glsl: the fragment test compares against the G-buffer's depth.
precise gl_Position;

void main() {
    worldPosition = inPosition;
    worldNormal = inNormal;
    reflectance = inReflectance;
    firstLayer = inLayer;
    gl_Position = pc.viewProj * vec4(inPosition, 1.0);
}
