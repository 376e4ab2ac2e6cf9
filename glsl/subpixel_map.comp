#version 460
// The sub-pixel aamap: each render pixel's predicted one-ray display error from its k x k
// samples and the ring of samples just outside it, as a map value (glsl/shared/subpixel_map.h
// has the rule; passes/cpu_subpixel.cpp is its CPU reference).
#extension GL_GOOGLE_include_directive : require
#include "aamap_filter.h"
#include "subpixel_map.h"
#include "snapshot_interface.h"
#include "display_luma.glsl"

layout(local_size_x = SUBPIXEL_GROUP_X, local_size_y = SUBPIXEL_GROUP_Y) in;
layout(push_constant) uniform Push { SubpixelPush pc; };
// k is fixed per pipeline so that the sample loops unroll to exactly k x k (lavapipe runs a loop
// bounded by a push constant, or masked lanes of a longer one, much slower).
layout(constant_id = SUBPIXEL_SPEC_K) const int K = SUBPIXEL_DEFAULT_K;

layout(binding = SUBPIXEL_BINDING_COLOUR, rgba32f) uniform readonly image2D colour;
layout(binding = SUBPIXEL_BINDING_NORMAL_DEPTH, rgba32f) uniform readonly image2D normalDepth;
layout(binding = SUBPIXEL_BINDING_IDS, rgba32f) uniform readonly image2D ids;
layout(binding = SUBPIXEL_BINDING_OUTPUT, r32f) uniform writeonly image2D aamap;

// core displayEncode: exposure, non-finite -> 0, clamp, sRGB.
float display(float linear) {
    precise float v = pc.exposure * linear;
    if (isnan(v) || isinf(v)) return 0.0;
    return srgbEncode(clamp(v, 0.0, 1.0));
}
vec3 display(vec3 rgb) { return vec3(display(rgb.r), display(rgb.g), display(rgb.b)); }
float maxOf(vec3 v) { return max(v.r, max(v.g, v.b)); }

// Step 3's test on one adjacent pair of samples.
bool geometryDiffers(ivec2 a, ivec2 b) {
    const vec4 na = imageLoad(normalDepth, a), nb = imageLoad(normalDepth, b);
    const bool ca = na.w > 0.0, cb = nb.w > 0.0;
    if (ca != cb) return true;
    if (!ca) return false;
    const vec4 ia = imageLoad(ids, a), ib = imageLoad(ids, b);
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
    const int k = K;
    const ivec2 base = k * p;
    const ivec2 size = k * pc.outSize;
    precise vec3 sum = vec3(0.0);
    for (int j = 0; j < k; ++j)
        for (int i = 0; i < k; ++i) sum += imageLoad(colour, base + ivec2(i, j)).rgb;
    const vec3 mean = display(sum / float(k * k));

    float own = 0.0;  // sum of the samples' deviations, row-major
    float error = 0.0;
    bool geometry = false;
    const ivec2 steps[4] = ivec2[4](ivec2(1, 0), ivec2(0, 1), ivec2(-1, 0), ivec2(0, -1));
    for (int j = 0; j < k; ++j)
        for (int i = 0; i < k; ++i) {
            const ivec2 s = base + ivec2(i, j);
            const vec3 ds = display(imageLoad(colour, s).rgb);
            own += maxOf(abs(ds - mean));
            for (int n = 0; n < 4; ++n) {
                const ivec2 o = ivec2(i, j) + steps[n];
                const bool inside = all(greaterThanEqual(o, ivec2(0))) && all(lessThan(o, ivec2(k)));
                if (inside && n >= 2) continue;  // pairs inside the pixel once (right and down)
                const ivec2 r = base + o;
                if (any(lessThan(r, ivec2(0))) || any(greaterThanEqual(r, size))) continue;
                if (!inside) error = max(error, 0.5 * maxOf(abs(display(imageLoad(colour, r).rgb) - ds)));
                if (!geometry && geometryDiffers(s, r)) geometry = true;
            }
        }
    error = max(error, own / float(k * k));
    const float tau = pc.tolerance;
    if (geometry) error = max(error, float(SUBPIXEL_GEOMETRY_ERROR) * tau);
    precise float a = error > tau ? 1.0 - tau / error : 0.0;
    imageStore(aamap, p, vec4(a));
}
