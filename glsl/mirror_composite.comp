#version 460
// snapshot += reflectance x the reflected colour, where mirror_mask marked a visible mirror.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_samplerless_texture_functions : require
#include "snapshot_interface.h"

layout(local_size_x = MIRROR_COMPOSITE_GROUP, local_size_y = MIRROR_COMPOSITE_GROUP) in;
layout(binding = MIRROR_COMPOSITE_BINDING_SNAPSHOT, rgba32f) uniform image2D snapshot;
layout(binding = MIRROR_COMPOSITE_BINDING_MASK, rgba32f) uniform readonly image2D mirrorMask;
layout(binding = MIRROR_COMPOSITE_BINDING_COLOUR) uniform texture2DArray mirrorColour;
layout(push_constant) uniform Push { MirrorCompositePush pc; };

void main() {
    const ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, pc.size))) return;
    const vec4 mask = imageLoad(mirrorMask, p);
    if (mask.a < 0.5) return;
    const vec3 reflected = texelFetch(mirrorColour, ivec3(p, int(mask.a - 0.5)), 0).rgb;
    const vec4 base = imageLoad(snapshot, p);
    imageStore(snapshot, p, vec4(base.rgb + mask.rgb * reflected, base.a));
}
