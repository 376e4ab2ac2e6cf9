// Writes the two images of geometric_edges.h, included by geometry_buffer.frag and its variants:
// normal (turned towards the camera, as the tracer and the Snapshot shading do) and view depth;
// object id, material id and the shadow occlusion mask. GEOMETRY_TEXTURED: the G-buffer's alpha
// test (cut-out texels are not covered). GEOMETRY_SHADOWS: the mask from the shadow cube maps.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_samplerless_texture_functions : require
#include "snapshot_interface.h"
#include "geometric_edges.h"

layout(location = 0) in vec3 worldPosition;
layout(location = 1) in vec3 worldNormal;
layout(location = 2) flat in uvec2 ids;
#ifdef GEOMETRY_TEXTURED
#include "gbuffer_texture.glsl"
layout(location = 3) in vec2 uv;
layout(location = 4) flat in uvec4 texRect;
layout(location = 5) flat in vec2 texParams;  // layer, alpha threshold
#ifdef GEOMETRY_SHADOWS
layout(binding = GEOMETRY_BINDING_ATLAS_SHADOWED) uniform texture2DArray atlas;
#else
layout(binding = GEOMETRY_BINDING_ATLAS_UNSHADOWED) uniform texture2DArray atlas;
#endif
#endif

layout(location = 0) out vec4 outNormalDepth;
layout(location = 1) out vec4 outIds;

layout(push_constant) uniform Push { GeometryPush pc; };

#ifdef GEOMETRY_SHADOWS
#include "lights.glsl"
#include "shadow_cube.glsl"
#include "shadow_visibility.glsl"
layout(std140, binding = GEOMETRY_BINDING_LIGHTS) uniform Lights { GpuLight lights[GBUFFER_MAX_LIGHTS]; };
layout(binding = GEOMETRY_BINDING_SHADOW) uniform texture2DArray shadowCubes;

// Bit (i mod 32) set when light i would light the texel (it faces the light, inside its lobe or
// cone: the G-buffer's weight > 0) but the shadow maps block at least half of its PCF kernel.
// Unlit sides never set a bit, so a terminator on a curved surface is no edge.
bool occludes(GpuLight light, uint i, vec3 n, vec4 shadow) {
    if (isDirectional(light))
        return dot(n, light.normal.xyz) > 0.0 &&
               directionalShadowVisibility(shadowCubes, i, light, worldPosition, n, vec4(shadow.xyz, light.position.w),
                                           int(kShadowPcf)) < 0.5;
    const vec3 toLight = light.position.xyz - worldPosition;
    const float d2 = dot(toLight, toLight);
    if (d2 <= 0.0) return false;
    const vec3 wi = toLight * inversesqrt(d2);
    // Not outside a spot's outer cone nor behind a lobe's emitter.
    const bool reaches = dot(n, wi) > 0.0 && angularFactor(light.normal.xyz, light.cone, wi) > 0.0;
    // Each light's faces have their own size (GpuLight::position.w).
    return reaches &&
           shadowVisibility(shadowCubes, i, -toLight, n, vec4(shadow.xyz, light.position.w), int(kShadowPcf)) < 0.5;
}

uint occlusionMask(vec3 n) {
    const vec4 shadow = pc.shadow;  // read once, as the G-buffer does (gbuffer.glsl)
    uint mask = 0u;
#define MASK_INLINE_LIGHT(k) \
    if (uint(k) < kLightCount && occludes(INLINE_LIGHT(k), uint(k), n, shadow)) mask |= 1u << uint(k);
    FOR_EACH_INLINE_LIGHT(MASK_INLINE_LIGHT)
    for (uint i = LIGHTING_INLINE_LIGHTS; i < kLightCount; ++i)
        if (occludes(lights[i], i, n, shadow)) mask |= 1u << (i & 31u);
    return mask;
}
#endif

void main() {
#ifdef GEOMETRY_TEXTURED
    if (texRect.z > 0u && atlasBilinear(atlas, uv, texRect, texParams.x).a < texParams.y) discard;
#endif
    const vec3 toEye = pc.cameraPos.xyz - worldPosition;
    vec3 n = normalize(worldNormal);
    if (dot(n, toEye) < 0.0) n = -n;
    // > 0 for anything in front of the near plane; the clear value 0 marks uncovered texels.
    const float depth = max(dot(worldPosition - pc.cameraPos.xyz, pc.cameraForward.xyz), 1e-30);
    outNormalDepth = vec4(n, depth);
    uint mask = 0u;
#ifdef GEOMETRY_SHADOWS
    mask = occlusionMask(n);
#endif
    // Halves of 16 bits: exact as floats, and never a NaN pattern an RGBA32F store could alter.
    outIds = vec4(float(ids.x & 0xffffffu), float(ids.y & 0xffffffu), float(mask & 0xffffu), float(mask >> 16u));
}
