#version 460
// Adds reflectance x what the curved mirror's probe sees in the reflected direction, where the
// mirror is the surface the camera sees (the depth test of mirror_mask.frag). Blended additively
// (alpha 0 under the premultiplied "over").
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_samplerless_texture_functions : require
#include "snapshot_interface.h"
#include "shadow_cube.glsl"

layout(location = 0) in vec3 worldPosition;
layout(location = 1) in vec3 worldNormal;
layout(location = 2) flat in vec3 reflectance;
layout(location = 3) flat in float firstLayer;
layout(location = 0) out vec4 outColour;

layout(push_constant) uniform Push { MirrorProbePush pc; };
layout(binding = MIRROR_PROBE_BINDING_DEPTH) uniform texture2D cameraDepth;
layout(binding = MIRROR_PROBE_BINDING_COLOUR) uniform texture2DArray probes;

void main() {
    const float nearest = texelFetch(cameraDepth, ivec2(gl_FragCoord.xy), 0).r;
    // Reversed depth: larger is nearer. A relative tolerance absorbs rounding differences.
    if (nearest > gl_FragCoord.z * (1.0 + 1e-4) + 1e-9) discard;
    const vec3 view = normalize(worldPosition - pc.cameraPos.xyz);
    vec3 n = normalize(worldNormal);
    if (dot(n, view) > 0.0) n = -n;  // two-sided, as the tracer's mirrors
    uint face;
    const vec3 f = cubeLookup(reflect(view, n), face);
    const int size = int(pc.cameraPos.w);
    const ivec2 texel = clamp(ivec2((f.xy / f.z * 0.5 + 0.5) * float(size)), ivec2(0), ivec2(size - 1));
    const vec3 seen = texelFetch(probes, ivec3(texel, int(firstLayer) + int(face)), 0).rgb;
    outColour = vec4(reflectance * seen, 0.0);
}
