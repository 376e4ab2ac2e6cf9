// The Snapshot raster's vertex stage, included by gbuffer.vert and gbuffer.textured.vert
// (GBUFFER_TEXTURED: also uv and the material's atlas entry), and their mirror variants
// (GBUFFER_MIRROR: gl_Layer from the push constants): world-space position and normal
// for per-pixel Lambert shading.
#extension GL_GOOGLE_include_directive : require
#ifdef GBUFFER_MIRROR
// The reflected view of one planar mirror per draw, into its layer of mirror.colour.
#extension GL_ARB_shader_viewport_layer_array : require
#endif
#include "snapshot_interface.h"

layout(location = GBUFFER_LOCATION_POSITION) in vec3 inPosition;
layout(location = GBUFFER_LOCATION_NORMAL) in vec3 inNormal;
layout(location = GBUFFER_LOCATION_KD) in vec3 inKd;
layout(location = GBUFFER_LOCATION_KE) in vec3 inKe;
layout(location = GBUFFER_LOCATION_SPECULAR) in vec4 inSpecular;
layout(location = GBUFFER_LOCATION_LOBE) in vec4 inLobe;
layout(location = GBUFFER_LOCATION_LOBE_ETA) in vec4 inLobeEta;
layout(location = GBUFFER_LOCATION_LOBE_K) in vec4 inLobeK;

layout(location = 0) out vec3 worldPosition;
layout(location = 1) out vec3 worldNormal;
layout(location = 2) flat out vec3 kd;
layout(location = 3) flat out vec3 ke;
layout(location = 7) flat out vec4 specular;  // after the textured outputs 4..6
layout(location = 8) flat out vec4 lobe;
layout(location = 9) flat out vec4 lobeEta;
layout(location = 10) flat out vec4 lobeK;

#ifdef GBUFFER_TEXTURED
layout(location = GBUFFER_LOCATION_UV) in vec2 inUv;
layout(location = GBUFFER_LOCATION_TEX_RECT) in uvec4 inTexRect;
layout(location = GBUFFER_LOCATION_TEX_PARAMS) in vec2 inTexParams;
layout(location = 4) out vec2 uv;
layout(location = 5) flat out uvec4 texRect;
layout(location = 6) flat out vec2 texParams;
#endif

layout(push_constant) uniform Push { GBufferPush pc; };

// As in gbuffer.depth.vert, whose depth the shading pass tests against for equality.
precise gl_Position;

void main() {
    worldPosition = inPosition;
    worldNormal = inNormal;
    kd = inKd;
    ke = inKe;
    specular = inSpecular;
    lobe = inLobe;
    lobeEta = inLobeEta;
    lobeK = inLobeK;
#ifdef GBUFFER_TEXTURED
    uv = inUv;
    texRect = inTexRect;
    texParams = inTexParams;
#endif
    gl_Position = pc.viewProj * vec4(inPosition, 1.0);
#ifdef GBUFFER_MIRROR
    gl_Layer = int(pc.mirrorLayer);
#endif
}
