#version 460
// Step 3 of the sub-pixel aamap (glsl/shared/subpixel_map.h), once per render pixel: whether an
// inside pair of its k x k geometry samples differs, and whether a boundary pair with the pixel to
// its right, and below it, does. subpixel_map.comp reads these flags for a pixel and its
// neighbours. Straight-line loads of each sample once: lavapipe runs a branchy pair test per
// lane far slower.
#extension GL_GOOGLE_include_directive : require
#include "subpixel_map.h"
#include "snapshot_interface.h"

layout(local_size_x = SUBPIXEL_GROUP_X, local_size_y = SUBPIXEL_GROUP_Y) in;
layout(push_constant) uniform Push { SubpixelPush pc; };
layout(constant_id = SUBPIXEL_SPEC_K) const int K = SUBPIXEL_DEFAULT_K;

layout(binding = SUBPIXEL_GEOMETRY_BINDING_NORMAL_DEPTH, rgba32f) uniform readonly image2D normalDepth;
layout(binding = SUBPIXEL_GEOMETRY_BINDING_IDS, rgba32f) uniform readonly image2D ids;
layout(binding = SUBPIXEL_GEOMETRY_BINDING_OUTPUT, r32f) uniform writeonly image2D flags;

// The test on one adjacent pair, from the loaded samples (normal and inverse depth, ids).
bool differs(vec4 na, vec4 ia, vec4 nb, vec4 ib) {
    const bool ca = na.w > 0.0, cb = nb.w > 0.0;
    if (ca != cb) return true;
    if (!ca) return false;
    if (ia.x != ib.x || ia.y != ib.y) return true;  // object, material
    precise float c = na.x * nb.x + na.y * nb.y + na.z * nb.z;
    if (c < float(SUBPIXEL_CREASE_COS)) return true;
    const float za = 1.0 / na.w, zb = 1.0 / nb.w;
    precise float jump = abs(za - zb);
    return jump > float(SUBPIXEL_DEPTH_TOLERANCE) * max(za, zb);
}

void main() {
    const ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, pc.outSize))) return;
    const ivec2 base = K * p;
    vec4 n[K][K], id[K][K];
    for (int j = 0; j < K; ++j)
        for (int i = 0; i < K; ++i) {
            n[j][i] = imageLoad(normalDepth, base + ivec2(i, j));
            id[j][i] = imageLoad(ids, base + ivec2(i, j));
        }
    bool own = false;
    for (int j = 0; j < K; ++j)
        for (int i = 0; i < K; ++i) {
            if (i + 1 < K) own = differs(n[j][i], id[j][i], n[j][i + 1], id[j][i + 1]) || own;
            if (j + 1 < K) own = differs(n[j][i], id[j][i], n[j + 1][i], id[j + 1][i]) || own;
        }
    bool right = false, down = false;
    for (int t = 0; t < K; ++t) {
        if (p.x + 1 < pc.outSize.x) {
            const ivec2 s = base + ivec2(K, t);
            right = differs(n[t][K - 1], id[t][K - 1], imageLoad(normalDepth, s), imageLoad(ids, s)) || right;
        }
        if (p.y + 1 < pc.outSize.y) {
            const ivec2 s = base + ivec2(t, K);
            down = differs(n[K - 1][t], id[K - 1][t], imageLoad(normalDepth, s), imageLoad(ids, s)) || down;
        }
    }
    const uint bits = (own ? SUBPIXEL_FLAG_OWN : 0u) | (right ? SUBPIXEL_FLAG_RIGHT : 0u) | (down ? SUBPIXEL_FLAG_DOWN : 0u);
    imageStore(flags, p, vec4(float(bits)));
}
