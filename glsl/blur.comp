#version 460
// Steps 3 and 4 of aamap_filter.h, fused: b = mean of e over the (2r+1)^2 clamped box (row-major
// sum, then one division, as on the CPU), m = clamp(gain * (b - noiseFloor), 0, 1).
// Each invocation computes AAMAP_FILTER_ROWS pixels of one column: every input row of the strip's
// window is loaded once and added to each output whose box holds it (rows in increasing order,
// taps left to right within a row, so each sum adds its taps in the same order as one pixel per
// invocation would): (ROWS + 2r)(2r + 1) loads for ROWS pixels instead of ROWS (2r + 1)^2.
#include "filter_common.glsl"

layout(binding = FILTER_BINDING_INPUT, r32f) uniform readonly image2D edges;
layout(binding = FILTER_BINDING_OUTPUT, r32f) uniform writeonly image2D map;

const int ROWS = AAMAP_FILTER_ROWS;
layout(constant_id = FILTER_SPEC_BLUR_RADIUS) const int kRadius = AAMAP_DEFAULT_BLUR_RADIUS;

void main() {
    const int x = int(gl_GlobalInvocationID.x);
    const int y0 = int(gl_GlobalInvocationID.y) * ROWS;
    if (x >= pc.inSize.x || y0 >= pc.inSize.y) return;
    const int r = kRadius;
    precise float sums[ROWS];
    for (int k = 0; k < ROWS; ++k) sums[k] = 0.0;
    for (int j = -r; j < ROWS + r; ++j) {
        const int y = clamp(y0 + j, 0, pc.inSize.y - 1);
        for (int dx = -r; dx <= r; ++dx) {
            const float v = imageLoad(edges, ivec2(clamp(x + dx, 0, pc.inSize.x - 1), y)).r;
            for (int k = 0; k < ROWS; ++k)
                if (abs(j - k) <= r) sums[k] += v;
        }
    }
    const int side = 2 * r + 1;
    for (int k = 0; k < ROWS; ++k) {
        if (y0 + k >= pc.inSize.y) break;
        precise float b = sums[k] / float(side * side);
        precise float m = clamp(pc.gain * (b - pc.noiseFloor), 0.0, 1.0);
        imageStore(map, ivec2(x, y0 + k), vec4(m));
    }
}
