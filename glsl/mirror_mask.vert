#version 460
// The mirror triangles from the camera, with each mirror's reflectance and layer (flat).
#extension GL_GOOGLE_include_directive : require
#include "snapshot_interface.h"

layout(location = MIRROR_MASK_LOCATION_POSITION) in vec3 inPosition;
layout(location = MIRROR_MASK_LOCATION_REFLECTANCE) in vec3 inReflectance;
layout(location = MIRROR_MASK_LOCATION_LAYER) in float inLayer;

layout(location = 0) flat out vec4 mask;

layout(push_constant) uniform Push { MirrorMaskPush pc; };

void main() {
    mask = vec4(inReflectance, inLayer + 1.0);
    gl_Position = pc.viewProj * vec4(inPosition, 1.0);
}
