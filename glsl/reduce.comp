#version 460
// The reduction of aamap_filter.h: aamap(x, y) = max of the map over every snapshot texel whose
// footprint overlaps pixel (x, y)'s footprint with non-zero length. Same integer spans as the
// CPU: texels [floor(i*src/dst), ceil((i+1)*src/dst)).
#include "filter_common.glsl"

layout(binding = FILTER_BINDING_INPUT, r32f) uniform readonly image2D map;
layout(binding = FILTER_BINDING_OUTPUT, r32f) uniform writeonly image2D aamap;

// floor(n / d) for 0 <= n < 2^31 and 0 < d < 2^24, without an integer division: lavapipe has no
// vector integer divide and runs one per lane, which made this pass the chain's slowest. The
// float quotient of such n and d (n / d < 2^22 here) is within 1 of the true one, and the two
// corrections make it exact.
int floorDiv(int n, int d) {
    int q = int(float(n) / float(d));
    q -= int(q * d > n);
    q += int((q + 1) * d <= n);
    return q;
}

ivec2 spanOf(int i, int src, int dst) { return ivec2(floorDiv(i * src, dst), floorDiv((i + 1) * src + dst - 1, dst)); }

void main() {
    const ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, pc.outSize))) return;
    const ivec2 xs = spanOf(p.x, pc.inSize.x, pc.outSize.x);
    const ivec2 ys = spanOf(p.y, pc.inSize.y, pc.outSize.y);
    float v = uintBitsToFloat(0xff800000u);  // -inf, as the CPU starts from
    for (int j = ys.x; j < ys.y; ++j)
        for (int i = xs.x; i < xs.y; ++i) v = max(v, imageLoad(map, ivec2(i, j)).r);
    imageStore(aamap, p, vec4(v));
}
