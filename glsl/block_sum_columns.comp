#version 460
// Block sums, step 2: one invocation per table column x in [0, W] accumulates the row prefixes
// downwards: S(x, 0) = 0, S(x, y + 1) = S(x, y) + R(x, y) (float-float), C likewise (exact uint).
// Output: the (W + 1) x (H + 1) tables of tracer/block_sums.h, row-major.
#include "block_sum_common.glsl"

layout(std430, binding = BLOCKSUM_COLUMNS_BINDING_ROW_SUMS) readonly buffer RowSums { vec2 rowSums[]; };
layout(std430, binding = BLOCKSUM_COLUMNS_BINDING_ROW_COUNTS) readonly buffer RowCounts { uint rowCounts[]; };
layout(std430, binding = BLOCKSUM_COLUMNS_BINDING_SUMS) writeonly buffer Sums { vec2 sums[]; };
layout(std430, binding = BLOCKSUM_COLUMNS_BINDING_COUNTS) writeonly buffer Counts { uint counts[]; };

void main() {
    const int x = int(gl_GlobalInvocationID.x);
    const int stride = pc.size.x + 1;
    if (x >= stride) return;
    vec2 sum = vec2(0.0);
    uint count = 0u;
    sums[x] = sum;
    counts[x] = count;
    for (int y = 0; y < pc.size.y; ++y) {
        sum = floatFloatAdd(sum, rowSums[y * stride + x]);
        count += rowCounts[y * stride + x];
        sums[(y + 1) * stride + x] = sum;
        counts[(y + 1) * stride + x] = count;
    }
}
