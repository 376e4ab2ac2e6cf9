#version 460
// Steps 3 and 4 of aamap_filter.h, fused: b = mean of e over the (2r+1)^2 clamped box (row-major
// sum, then one division, as on the CPU), m = clamp(gain * (b - noiseFloor), 0, 1).
#include "filter_common.glsl"

layout(binding = FILTER_BINDING_INPUT, r32f) uniform readonly image2D edges;
layout(binding = FILTER_BINDING_OUTPUT, r32f) uniform writeonly image2D map;

void main() {
    const ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, pc.inSize))) return;
    const int r = pc.radius;
    precise float sum = 0.0;
    for (int dy = -r; dy <= r; ++dy)
        for (int dx = -r; dx <= r; ++dx) sum += imageLoad(edges, clampToImage(p + ivec2(dx, dy), pc.inSize)).r;
    const int side = 2 * r + 1;
    precise float b = sum / float(side * side);
    precise float m = clamp(pc.gain * (b - pc.noiseFloor), 0.0, 1.0);
    imageStore(map, p, vec4(m));
}
