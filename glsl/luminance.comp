#version 460
// Step 1 of aamap_filter.h (display_luma.glsl) over the snapshot colour, for Snapshots whose
// G-buffer does not write the grey itself (a mirror composite follows it; passes/gbuffer.h).
#include "filter_common.glsl"
#include "display_luma.glsl"

layout(binding = FILTER_BINDING_INPUT, rgba32f) uniform readonly image2D colour;
layout(binding = FILTER_BINDING_OUTPUT, r32f) uniform writeonly image2D grey;

void main() {
    const ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, pc.inSize))) return;
    imageStore(grey, p, vec4(displayLuma(imageLoad(colour, p).rgb, pc.exposure)));
}
