#version 460
// Step 2 of aamap_filter.h: e = |sum over the 24 off-centre taps of (g(p+o) - g(p))|, taps in
// row-major order, edges clamped. `precise` keeps the CPU's accumulation order bit for bit.
#include "filter_common.glsl"

layout(binding = FILTER_BINDING_INPUT, r32f) uniform readonly image2D grey;
layout(binding = FILTER_BINDING_OUTPUT, r32f) uniform writeonly image2D edges;

void main() {
    const ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, pc.inSize))) return;
    const float centre = imageLoad(grey, p).r;
    precise float sum = 0.0;
    for (int dy = -AAMAP_LAPLACIAN_RADIUS; dy <= AAMAP_LAPLACIAN_RADIUS; ++dy) {
        for (int dx = -AAMAP_LAPLACIAN_RADIUS; dx <= AAMAP_LAPLACIAN_RADIUS; ++dx) {
            if (dx == 0 && dy == 0) continue;
            sum += imageLoad(grey, clampToImage(p + ivec2(dx, dy), pc.inSize)).r - centre;
        }
    }
    imageStore(edges, p, vec4(abs(sum)));
}
