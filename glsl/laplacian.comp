#version 460
// Step 2 of aamap_filter.h: e = |sum over the 24 off-centre taps of (g(p+o) - g(p))|, taps in
// row-major order, edges clamped, and 0 where the 3x3 window's range is below pc.flatRange (the
// flat gate; min, max and one subtraction are exact, so the CPU decides alike).
// `precise` keeps the CPU's accumulation order bit for bit.
// Each invocation computes AAMAP_FILTER_ROWS pixels of one column (a strip), keeping the strip's
// (ROWS + 4) x 5 window in registers: 10 image loads per pixel at 4 rows instead of 25, and no
// shared memory (whose barriers cost more than the loads on lavapipe). Same values, same order.
#include "filter_common.glsl"

layout(binding = FILTER_BINDING_INPUT, r32f) uniform readonly image2D grey;
layout(binding = FILTER_BINDING_OUTPUT, r32f) uniform writeonly image2D edges;

const int R = AAMAP_LAPLACIAN_RADIUS;
const int ROWS = AAMAP_FILTER_ROWS;
const int SIDE = 2 * R + 1;
const int G = AAMAP_FLAT_GATE_RADIUS;

void main() {
    const int x = int(gl_GlobalInvocationID.x);
    const int y0 = int(gl_GlobalInvocationID.y) * ROWS;
    if (x >= pc.inSize.x || y0 >= pc.inSize.y) return;
    float window[ROWS + 2 * R][SIDE];
    for (int r = 0; r < ROWS + 2 * R; ++r) {
        const int y = clamp(y0 - R + r, 0, pc.inSize.y - 1);
        for (int c = 0; c < SIDE; ++c) window[r][c] = imageLoad(grey, ivec2(clamp(x - R + c, 0, pc.inSize.x - 1), y)).r;
    }
    for (int k = 0; k < ROWS; ++k) {
        if (y0 + k >= pc.inSize.y) break;
        const float centre = window[k + R][R];
        precise float sum = 0.0;
        for (int dy = -R; dy <= R; ++dy) {
            for (int dx = -R; dx <= R; ++dx) {
                if (dx == 0 && dy == 0) continue;
                sum += window[k + R + dy][R + dx] - centre;
            }
        }
        float lo = centre, hi = centre;
        for (int dy = -G; dy <= G; ++dy) {
            for (int dx = -G; dx <= G; ++dx) {
                lo = min(lo, window[k + R + dy][R + dx]);
                hi = max(hi, window[k + R + dy][R + dx]);
            }
        }
        imageStore(edges, ivec2(x, y0 + k), vec4(pc.flatRange <= 0.0 || hi - lo >= pc.flatRange ? abs(sum) : 0.0));
    }
}
