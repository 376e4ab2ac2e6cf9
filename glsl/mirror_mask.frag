#version 460
// Writes (reflectance, layer + 1) where the mirror is the surface the camera sees: its depth is
// the G-buffer's (same vertices, same matrix) up to rounding; anything nearer hides it.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_samplerless_texture_functions : require
#include "snapshot_interface.h"

layout(location = 0) flat in vec4 mask;
layout(location = 0) out vec4 outMask;

layout(binding = MIRROR_MASK_BINDING_DEPTH) uniform texture2D cameraDepth;

void main() {
    const float nearest = texelFetch(cameraDepth, ivec2(gl_FragCoord.xy), 0).r;
    // Reversed depth: larger is nearer. A relative tolerance absorbs rounding differences.
    if (nearest > gl_FragCoord.z * (1.0 + 1e-4) + 1e-9) discard;
    outMask = mask;
}
