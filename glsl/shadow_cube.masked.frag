#version 460
// Depth only, with the alpha test of the G-buffer: cut-out texels cast no shadow.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_samplerless_texture_functions : require
#include "snapshot_interface.h"
#include "gbuffer_texture.glsl"

layout(location = 0) in vec2 uv;
layout(location = 1) flat in uvec4 texRect;
layout(location = 2) flat in vec2 texParams;  // layer, alpha threshold

layout(binding = SHADOW_BINDING_ATLAS) uniform texture2DArray atlas;

void main() {
    if (texRect.z > 0u && texParams.y > 0.0 && atlasBilinear(atlas, uv, texRect, texParams.x).a < texParams.y) discard;
}
