// Float-float arithmetic for the block-sum tables (GLSL only). `precise` keeps the compiler
// from fusing or reordering the error terms, which would make them zero.
#extension GL_GOOGLE_include_directive : require
#include "snapshot_interface.h"

layout(local_size_x = BLOCKSUM_GROUP) in;
layout(push_constant) uniform Push { BlockSumPush pc; };

// (hi, lo) + (b.hi, b.lo), renormalised so that |lo| <= ulp(hi) / 2 (Knuth's TwoSum on the highs).
vec2 floatFloatAdd(vec2 a, vec2 b) {
    precise float s = a.x + b.x;
    precise float v = s - a.x;
    precise float e = (a.x - (s - v)) + (b.x - v);
    precise float t = e + (a.y + b.y);
    precise float hi = s + t;
    precise float lo = t - (hi - s);
    return vec2(hi, lo);
}
