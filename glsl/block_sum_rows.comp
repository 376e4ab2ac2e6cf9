#version 460
// Block sums, step 1: one invocation per aamap row y writes the row prefixes
//   R(0, y) = 0,  R(x + 1, y) = sum of v(i, y) for i <= x  (float-float),  N likewise counting v > 0,
// with v = clamp(aamap, 0, 1) and NaN -> 1 (tracer/block_sums.h). Layout (W + 1) x H, row-major.
#include "block_sum_common.glsl"

layout(binding = BLOCKSUM_ROWS_BINDING_MAP, r32f) uniform readonly image2D map;
layout(std430, binding = BLOCKSUM_ROWS_BINDING_SUMS) writeonly buffer RowSums { vec2 rowSums[]; };
layout(std430, binding = BLOCKSUM_ROWS_BINDING_COUNTS) writeonly buffer RowCounts { uint rowCounts[]; };

void main() {
    const int y = int(gl_GlobalInvocationID.x);
    if (y >= pc.size.y) return;
    const int stride = pc.size.x + 1;
    vec2 sum = vec2(0.0);
    uint count = 0u;
    rowSums[y * stride] = sum;
    rowCounts[y * stride] = count;
    for (int x = 0; x < pc.size.x; ++x) {
        // Decided on the bits: a device that flushes denormals still counts them as non-zero.
        const uint bits = floatBitsToUint(imageLoad(map, ivec2(x, y)).r);
        const bool nan = (bits & 0x7fffffffu) > 0x7f800000u;
        const bool positive = bits != 0u && (bits & 0x80000000u) == 0u;
        const float v = nan ? 1.0 : clamp(uintBitsToFloat(bits), 0.0, 1.0);
        sum = floatFloatAdd(sum, vec2(v, 0.0));
        count += (nan || positive) ? 1u : 0u;
        rowSums[y * stride + x + 1] = sum;
        rowCounts[y * stride + x + 1] = count;
    }
}
